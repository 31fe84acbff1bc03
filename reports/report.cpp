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
  db::write_text_file_atomically(index, report_html(data, generated.empty() ? local_time_now() : generated));
  return index;
}

}  // namespace yarnfit::reports
