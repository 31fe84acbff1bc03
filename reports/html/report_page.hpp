#pragma once
// index.html of `yarnfit report`: one self-contained page (inline SVG and CSS, no script,
// no external resource) with the summary, the Table 6.1-style statistics per family, the
// Fig. 6.13/6.15-style error plots, what accuracy cost in time across runs, and a section
// per fabric (curves, parameters in their bounds, identifiability, time, effects).
//
// Plots are tagged for tools and tests: every <svg> has class "plot" and data-plot (overview,
// family, cost, fabric, fabric-shell-force, …); family plots carry data-family, fabric plots
// data-fabric. Each family has exactly one data-plot="family", each fabric one data-plot="fabric".

#include <filesystem>
#include <string>

#include "reports/collection/report_data.hpp"

namespace yarnfit::reports {

// `generated` is shown as the page's date (the caller's clock, so that tests can fix it); links
// to a fabric's files are relative to `report_dir`, the folder the page is written to.
std::string report_html(const ReportData& data, const std::string& generated,
                        const std::filesystem::path& report_dir = {});

}  // namespace yarnfit::reports
