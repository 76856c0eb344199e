#include <cmath>
#include <string>

#include "html_text.h"
#include "tether/viewer/view.h"
#include "view_assets.h"

namespace tether {
namespace {

// A run's frames and series as the player reads them.
nlohmann::json RunJson(const ViewFrames& frames) {
  nlohmann::json series = nlohmann::json::array();
  for (const std::vector<double>& row : frames.series) series.push_back(NumbersOrNull(row));
  return {{"frames", {{"times", frames.times}, {"poses", frames.poses}}},
          {"series", {{"names", frames.series_names}, {"values", series}}}};
}

// An impact's impulse's unit: a contact's N s; a limit's N m s on an angle, N s on a displacement.
std::string ImpulseUnit(const Model<double>& model, const ViewEvent& event) {
  if (event.normal.squaredNorm() > 0.0) return "N s";
  for (const Joint<double>& joint : model.joints) {
    if (joint.name == event.constraint || "/constraints/" + std::to_string(joint.scene_index) == event.constraint) {
      return joint.type == JointType::kSlider || joint.type == JointType::kPrismatic ? "N s" : "N m s";
    }
  }
  return "N s";
}

}  // namespace

nlohmann::json NumbersOrNull(const std::vector<double>& values) {
  nlohmann::json out = nlohmann::json::array();
  for (const double x : values) out.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json());
  return out;
}

nlohmann::json ViewData(const Model<double>& model, const ViewFrames& frames, const ViewFrames* ghost) {
  nlohmann::json events = nlohmann::json::array();
  for (const ViewEvent& e : frames.events) {
    events.push_back({{"t", e.t},
                      {"kind", e.kind},
                      {"constraint", e.constraint},
                      {"point", {e.point.x(), e.point.y(), e.point.z()}},
                      {"normal", {e.normal.x(), e.normal.y(), e.normal.z()}},
                      {"impulse", e.impulse},
                      {"unit", ImpulseUnit(model, e)}});
  }
  nlohmann::json data = RunJson(frames);
  data["drawing"] = ViewDrawing(model);
  data["events"] = events;
  data["ghost"] = ghost ? RunJson(*ghost) : nlohmann::json();
  return data;
}

std::string ViewTemplate(const std::string& title) {
  std::string page(viewer_assets::Page());
  size_t from = 0;  // the markers in the order they appear
  html::Replace(&page, "@TITLE@", html::Escaped(title), &from);
  from = page.find("@DATA@", from) + 6;  // left for the data
  html::Replace(&page, "@THREE@", viewer_assets::Three(), &from);
  html::Replace(&page, "@ORBIT_CONTROLS@", viewer_assets::OrbitControls(), &from);
  html::Replace(&page, "@PLAYER@", viewer_assets::Player(), &from);
  return page;
}

std::string ViewHtml(const Model<double>& model, const std::string& title, const ViewFrames& frames,
                     const ViewFrames* ghost) {
  std::string page = ViewTemplate(title);
  size_t from = 0;
  html::Replace(&page, "@DATA@", html::InScript(ViewData(model, frames, ghost).dump()), &from);
  return page;
}

}  // namespace tether
