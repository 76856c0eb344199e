#include <cmath>
#include <string>

#include "tether/viewer/view.h"
#include "view_assets.h"

namespace tether {
namespace {

// Text for an HTML element's content.
std::string Escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else {
      out += c;
    }
  }
  return out;
}

// A script's text never holds "</" (which could end its element early): JSON may write "<\/", JavaScript
// libraries are inlined as they are (three.js holds none).
std::string InScript(const std::string& json_text) {
  std::string out;
  for (size_t i = 0; i < json_text.size(); ++i) {
    out += json_text[i];
    if (json_text[i] == '<' && i + 1 < json_text.size() && json_text[i + 1] == '/') out += '\\';
  }
  return out;
}

// Replaces the first `marker` at or after *from, and moves *from past the text put in: no inlined text (a body
// named @PLAYER@) is searched again.
void Replace(std::string* page, const std::string& marker, std::string_view text, size_t* from) {
  const size_t at = page->find(marker, *from);
  page->replace(at, marker.size(), text);
  *from = at + text.size();
}

// A run's frames and series as the player reads them.
nlohmann::json RunJson(const ViewFrames& frames) {
  nlohmann::json series = nlohmann::json::array();  // NaN (not in JSON) as null
  for (const std::vector<double>& row : frames.series) {
    nlohmann::json values = nlohmann::json::array();
    for (const double x : row) values.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json());
    series.push_back(values);
  }
  return {{"frames", {{"times", frames.times}, {"poses", frames.poses}}},
          {"series", {{"names", frames.series_names}, {"values", series}}}};
}

}  // namespace

std::string ViewHtml(const Model<double>& model, const std::string& title, const ViewFrames& frames,
                     const ViewFrames* ghost) {
  nlohmann::json events = nlohmann::json::array();
  for (const ViewEvent& e : frames.events) {
    events.push_back({{"t", e.t},
                      {"kind", e.kind},
                      {"constraint", e.constraint},
                      {"point", {e.point.x(), e.point.y(), e.point.z()}},
                      {"normal", {e.normal.x(), e.normal.y(), e.normal.z()}},
                      {"impulse", e.impulse}});
  }
  nlohmann::json data = RunJson(frames);
  data["drawing"] = ViewDrawing(model);
  data["events"] = events;
  data["ghost"] = ghost ? RunJson(*ghost) : nlohmann::json();
  std::string page(viewer_assets::Page());
  size_t from = 0;  // the markers in the order they appear
  Replace(&page, "@TITLE@", Escaped(title), &from);
  Replace(&page, "@DATA@", InScript(data.dump()), &from);
  Replace(&page, "@THREE@", viewer_assets::Three(), &from);
  Replace(&page, "@ORBIT_CONTROLS@", viewer_assets::OrbitControls(), &from);
  Replace(&page, "@PLAYER@", viewer_assets::Player(), &from);
  return page;
}

}  // namespace tether
