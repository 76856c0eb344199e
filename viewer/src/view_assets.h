// The page's parts, inlined into the library at build time (viewer/CMakeLists.txt names the files): Debian's
// three.js and its OrbitControls, and tether's templates and scripts (viewer/assets): the viewer's page and player,
// the fit report's page and script, a study index's page and script.
#pragma once

#include <string_view>

namespace tether::viewer_assets {

std::string_view Three();
std::string_view OrbitControls();
std::string_view Page();
std::string_view Player();
std::string_view ReportPage();
std::string_view ReportScript();
std::string_view StudyPage();
std::string_view StudyScript();

}  // namespace tether::viewer_assets
