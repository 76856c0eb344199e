// `tether view` (docs/view.md): one self-contained HTML file that plays a motion. The page carries three.js (Debian's
// libjs-three, inlined), its OrbitControls, tether's player (viewer/assets/player.js) and the run as JSON: what to
// draw (bodies from their shapes, else a glyph from mass and inertia; joints at their anchors with their axes;
// distance constraints as rods; markers; the world's shapes) and the poses of the bodies frame by frame.
//
// A glyph is the body as a uniform solid of its mass and inertia: a particle is a sphere of a twentieth of the
// scene's length scale; a 3D rigid body the box whose principal moments are its own, edges
//   a_k = sqrt(6 (I_1 + I_2 + I_3 - 2 I_k) / m)   (I_k = m (a_i^2 + a_j^2) / 12),
// along its principal axes; a planar one the square plate of its moment, side sqrt(6 I / m).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/dynamics/io/trajectory_columns.h"
#include "tether/dynamics/model/model.h"

namespace tether {

// A run at the frames to draw: each body's position and orientation [x, y, z, qw, qx, qy, qz] (a planar body turns
// about z; a particle's orientation is the identity), the series the page can plot beside the motion (a simulated
// run's joint coordinates, markers, constraint error and energy; a CSV's columns other than the poses) and the
// run's events (a simulated run's impacts, releases, stick and slip: where, and an impact's impulse, as RunEvent).
struct ViewEvent {
  double t = 0.0;
  std::string kind, constraint;
  Vec3<double> point = Vec3<double>::Zero(), normal = Vec3<double>::Zero();
  double impulse = 0.0;
};
struct ViewFrames {
  std::vector<double> times;
  std::vector<std::vector<double>> poses;  // poses[frame]: 7 numbers per body, in body order (none: not posed)
  std::vector<std::string> series_names;
  std::vector<std::vector<double>> series;  // series[frame][k]: series_names[k]'s value, NaN where not recorded
  std::vector<ViewEvent> events;
  std::vector<std::string> warnings;  // a simulated run's (RunReport::warnings), for the caller to show
};

// Frames are kept at most this often (the page interpolates nothing: it shows the frame at or before the time).
inline constexpr double kViewFramesPerSecond = 60.0;

// A page holds at most this many numbers (about 20 bytes each in its JSON: 400 MB, which browsers still open).
inline constexpr double kMostViewNumbers = 2e7;

// Throws InputError, naming `source`, when `frames` frames of the model's bodies and `series` series would pass
// kMostViewNumbers: checked before a run (its planned frames) and before a page is written.
void CheckViewSize(const Model<double>& model, double frames, size_t series, const std::string& source);

// The scene simulated, a frame every 1 / kViewFramesPerSecond s (and the last state). Throws what Simulate throws.
ViewFrames SimulatedFrames(const Model<double>& model);

// The frames of a run's rows: row r at times[r] with configuration q_of_row(r) and the series' values
// series_of_row(r) (names `series_names`); rows less than 1 / frames_per_second after the last frame kept are
// skipped, the last row is always kept. `source` names the run in messages.
ViewFrames SampledFrames(const std::string& source, const Model<double>& model, const std::vector<double>& times,
                         const std::function<VecX<double>(size_t)>& q_of_row,
                         const std::vector<std::string>& series_names,
                         const std::function<std::vector<double>(size_t)>& series_of_row,
                         double frames_per_second = kViewFramesPerSecond);

// Whether a trajectory column is a series the page plots for a simulated run: joint coordinates, markers, the
// constraint error and the energy.
bool PlottedColumn(const TrajectoryColumn& column);

// The frames of a trajectory CSV (docs/contract.md) recorded or simulated for the scene: every body's position
// and orientation columns must be there; rows at most kViewFramesPerSecond apart in time are skipped, the last
// row is always kept. Throws InputError naming the file and the column or line.
ViewFrames RecordedFrames(const Model<double>& model, const std::string& csv_path);

// The same from observations read already (`data.path` names them in messages). Without `poses_required`, a
// recording that lacks some body's pose columns gives its series alone: frames with no poses, which the page draws
// no ghost for.
ViewFrames ObservedFrames(const Model<double>& model, const Observations& data, bool poses_required);

// What the page draws, as JSON (view.h's header; docs/view.md lists the fields).
nlohmann::json ViewDrawing(const Model<double>& model);

// Numbers as the pages' JSON holds them: one that is not finite (NaN, which JSON lacks) as null.
nlohmann::json NumbersOrNull(const std::vector<double>& values);

// What the player draws and plays, as the JSON the page carries: the drawing, the frames, their series and events,
// and the ghost's (null without one).
nlohmann::json ViewData(const Model<double>& model, const ViewFrames& frames, const ViewFrames* ghost);

// The page with everything inlined but the data: the marker @DATA@ stands where ViewData's JSON goes (as a script's
// text: "</" written "<\/"), once, after the title.
std::string ViewTemplate(const std::string& title);

// The HTML page: `title` in its title bar, the drawing and the frames; with `ghost`, a second run of the scene (a
// recording beside the simulation) drawn translucent and grey, its series plotted dashed beside the run's.
std::string ViewHtml(const Model<double>& model, const std::string& title, const ViewFrames& frames,
                     const ViewFrames* ghost = nullptr);

}  // namespace tether
