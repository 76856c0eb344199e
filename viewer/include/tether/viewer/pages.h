// The pages beside the viewer's (docs/reports.md), each one self-contained HTML file like the viewer's: the JSON
// its script draws from, inlined, and the viewer's pages of runs inside it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace tether {

// The report of an identification or a fit: `report` is the JSON viewer/assets/report.js draws (the fields
// cli/fit_report.cc writes), `view_page` the viewer's page of the estimate's run (shown in a frame; empty: none).
std::string ReportHtml(const std::string& title, const nlohmann::json& report, const std::string& view_page);

}  // namespace tether
