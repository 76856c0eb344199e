// The page's parts, inlined into the library at build time (viewer/CMakeLists.txt names the files): Debian's
// three.js and its OrbitControls, and tether's page template and player (viewer/assets).
#pragma once

#include <string_view>

namespace tether::viewer_assets {

std::string_view Three();
std::string_view OrbitControls();
std::string_view Page();
std::string_view Player();

}  // namespace tether::viewer_assets
