#include "html_text.h"
#include "tether/viewer/pages.h"
#include "view_assets.h"

namespace tether {

std::string ReportHtml(const std::string& title, const nlohmann::json& report, const std::string& view_page) {
  std::string page(viewer_assets::ReportPage());
  size_t from = 0;  // the markers in the order they appear
  html::Replace(&page, "@TITLE@", html::Escaped(title), &from);
  html::Replace(&page, "@TITLE@", html::Escaped(title), &from);
  html::Replace(&page, "@VIEW@", html::AttributeEscaped(view_page), &from);
  html::Replace(&page, "@DATA@", html::InScript(report.dump()), &from);
  html::Replace(&page, "@REPORT@", viewer_assets::ReportScript(), &from);
  return page;
}

}  // namespace tether
