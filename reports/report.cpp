#include "reports/report.hpp"

#include <chrono>
#include <ctime>

#include "fabrics_db/text_util.hpp"
#include "reports/html/report_page.hpp"

namespace yarnfit::reports {

namespace {

std::string local_time_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[64];
  std::strftime(text, sizeof text, "generated %Y-%m-%d %H:%M", &tm);
  return text;
}

}  // namespace

std::filesystem::path write_report(const ReportData& data, const std::filesystem::path& out,
                                   const std::string& generated) {
  std::filesystem::create_directories(out);
  db::write_text_file_atomically(out / "report.json", report_json(data).dump(2) + "\n");
  db::write_text_file_atomically(out / "fabrics.csv", fabrics_csv(data));
  db::write_text_file_atomically(out / "families.csv", families_csv(data));
  const auto index = out / "index.html";
  db::write_text_file_atomically(index, report_html(data, generated.empty() ? local_time_now() : generated, out));
  return index;
}

std::string report_written_line(const ReportData& data, const std::filesystem::path& index) {
  int failed = 0;
  for (const auto& r : data.fabrics) failed += r.status != "done";
  const auto plural = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  return "report of " + plural(data.fabrics.size(), "fabric", "fabrics") + " (" +
         plural(data.families.size(), "family", "families") + ", " + std::to_string(failed) + " not fitted) from " +
         plural(data.run_summaries.size(), "run", "runs") +
         ": open " + std::filesystem::absolute(index).lexically_normal().string() + "\n";
}

}  // namespace yarnfit::reports
