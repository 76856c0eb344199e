#include "view_assets.h"

// Each file between two symbols in read-only data (the assembler's .incbin), with no copy at run time.
#define TETHER_INCBIN(name, path)                                                                                    \
  __asm__(".pushsection .rodata\n.global " #name "\n" #name ":\n.incbin \"" path "\"\n.global " #name "_end\n" #name \
          "_end:\n.popsection\n");                                                                                   \
  extern "C" const char name[];                                                                                      \
  extern "C" const char name##_end[];

TETHER_INCBIN(tether_view_three, TETHER_VIEW_THREE_JS)
TETHER_INCBIN(tether_view_orbit_controls, TETHER_VIEW_ORBIT_CONTROLS_JS)
TETHER_INCBIN(tether_view_page, TETHER_VIEW_PAGE_HTML)
TETHER_INCBIN(tether_view_player, TETHER_VIEW_PLAYER_JS)
TETHER_INCBIN(tether_report_page, TETHER_REPORT_PAGE_HTML)
TETHER_INCBIN(tether_report_script, TETHER_REPORT_JS)
TETHER_INCBIN(tether_study_page, TETHER_STUDY_PAGE_HTML)
TETHER_INCBIN(tether_study_script, TETHER_STUDY_JS)

namespace tether::viewer_assets {

std::string_view Three() { return {tether_view_three, static_cast<size_t>(tether_view_three_end - tether_view_three)}; }
std::string_view OrbitControls() {
  return {tether_view_orbit_controls, static_cast<size_t>(tether_view_orbit_controls_end - tether_view_orbit_controls)};
}
std::string_view Page() { return {tether_view_page, static_cast<size_t>(tether_view_page_end - tether_view_page)}; }
std::string_view Player() {
  return {tether_view_player, static_cast<size_t>(tether_view_player_end - tether_view_player)};
}
std::string_view ReportPage() {
  return {tether_report_page, static_cast<size_t>(tether_report_page_end - tether_report_page)};
}
std::string_view ReportScript() {
  return {tether_report_script, static_cast<size_t>(tether_report_script_end - tether_report_script)};
}
std::string_view StudyPage() {
  return {tether_study_page, static_cast<size_t>(tether_study_page_end - tether_study_page)};
}
std::string_view StudyScript() {
  return {tether_study_script, static_cast<size_t>(tether_study_script_end - tether_study_script)};
}

}  // namespace tether::viewer_assets
