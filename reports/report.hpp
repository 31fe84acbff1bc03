#pragma once
// `yarnfit report` as a library: the report of one or more runs (batch outputs or folders of
// `yarnfit fit` outputs) written to a folder as index.html, fabrics.csv, families.csv and
// report.json (SPEC §5), each file whole or not at all.
//
//   std::vector<reports::RunOutputs> runs{reports::read_fit_folders("fits/")};
//   reports::write_report(reports::make_report_data(std::move(runs)), "report/");

#include <filesystem>
#include <string>

#include "reports/collection/fit_outputs.hpp"
#include "reports/collection/report_data.hpp"

namespace yarnfit::reports {

// Writes the four files into `out` (created if needed); `generated` is the date line of the
// page (the local time when empty). Returns the path of index.html.
std::filesystem::path write_report(const ReportData& data, const std::filesystem::path& out,
                                   const std::string& generated = "");

// The line that says a report was written: how many fabrics, families, failures and runs, and
// the absolute path of `index` to open.
[[nodiscard]] std::string report_written_line(const ReportData& data, const std::filesystem::path& index);

}  // namespace yarnfit::reports
