#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "html_text.h"
#include "tether/viewer/pages.h"
#include "view_assets.h"

namespace tether {
namespace {

// x to 4 significant digits (a tenth of a millimetre a metre from the origin: finer than a pixel; the JSON then
// writes its shortest form).
double Rounded(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return std::strtod(text, nullptr);
}

// Every number of an array of arrays to 4 significant digits, whole numbers written as integers (a particle's
// orientation, a planar body's z: 0 rather than 0.0); nulls stay.
void RoundAll(nlohmann::json* rows) {
  for (nlohmann::json& row : *rows) {
    for (nlohmann::json& x : row) {
      if (!x.is_number()) continue;
      const double rounded = Rounded(x.get<double>());
      const bool whole = rounded == std::trunc(rounded) && std::abs(rounded) < 1e9;
      x = whole ? nlohmann::json(static_cast<std::int64_t>(rounded)) : nlohmann::json(rounded);
    }
  }
}

}  // namespace

std::string StudyRowScript(int index, const nlohmann::json& values, const Model<double>& model,
                           const ViewFrames& frames) {
  nlohmann::json data = ViewData(model, frames, nullptr);
  RoundAll(&data["frames"]["poses"]);
  RoundAll(&data["series"]["values"]);
  data["row"] = index;
  data["values"] = values;
  return "tetherStudyRow(" + html::InScript(data.dump()) + ");\n";  // data.row says which
}

std::string StudyIndexHtml(const std::string& title, const nlohmann::json& study) {
  std::string page(viewer_assets::StudyPage());
  size_t from = 0;  // the markers in the order they appear
  html::Replace(&page, "@TITLE@", html::Escaped(title), &from);
  html::Replace(&page, "@TITLE@", html::Escaped(title), &from);
  html::Replace(&page, "@DATA@", html::InScript(study.dump()), &from);
  html::Replace(&page, "@VIEWER@", html::InScript(nlohmann::json(ViewTemplate(title)).dump()), &from);
  html::Replace(&page, "@STUDY@", viewer_assets::StudyScript(), &from);
  return page;
}

}  // namespace tether
