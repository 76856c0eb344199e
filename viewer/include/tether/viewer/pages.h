// The pages beside the viewer's (docs/reports.md), each one self-contained HTML file like the viewer's: the JSON
// its script draws from, inlined, and the viewer's pages of runs inside it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "tether/viewer/view.h"

namespace tether {

// The report of an identification or a fit: `report` is the JSON viewer/assets/report.js draws (the fields
// cli/fit_report.cc writes), `view_page` the viewer's page of the estimate's run (shown in a frame; empty: none).
std::string ReportHtml(const std::string& title, const nlohmann::json& report, const std::string& view_page);

// A study's rows are kept at this many frames a second (a study has many: 520 runs of 3 s for the stability maps).
inline constexpr double kStudyFramesPerSecond = 30.0;

// DIR/views/ROW.js of a study (docs/reports.md): the script that hands the index the row's index, its swept values
// and the player's data of its run (ViewData), positions and series to 4 significant digits:
// tetherStudyRow(DATA), DATA.row the index, DATA.values the swept values.
std::string StudyRowScript(int index, const nlohmann::json& values, const Model<double>& model,
                           const ViewFrames& frames);

// DIR/index.html of a study: `study` is the JSON viewer/assets/study.js draws (the fields cli/study_index.cc
// writes); the viewer's page template goes in once, each row's data from its views/ROW.js when asked.
std::string StudyIndexHtml(const std::string& title, const nlohmann::json& study);

}  // namespace tether
