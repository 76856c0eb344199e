#include "fit_plot.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "matplotlib_script.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/trajectory_columns.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"

namespace tether::cli {
namespace {

// argv: fitted.csv output.png [data.csv ...] [bound:COLUMN:FROM:T:VALUE:least|most ...]
//       [unit:COLUMN:UNIT ...] [schedule:LABEL:T0,T1,...:V0,V1,... ...]   (FROM = T: at T)
// A panel per observed or bounded column (its unit on the axis), then one per scheduled force or torque the fit
// may have set, drawn through its knots as the simulation interpolates them (linearly).
constexpr const char* kScript = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
plt.rcParams["svg.fonttype"] = "none"  # an SVG's labels stay text (searchable, and smaller)

def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k.strip(): [float(r[k]) if r[k].strip() else None for r in rows] for k in rows[0]}

def tagged(tag):
    return [a[len(tag) + 1:] for a in sys.argv[3:] if a.startswith(tag + ":")]

fitted, out = read(sys.argv[1]), sys.argv[2]
data = [(p, read(p)) for p in sys.argv[3:] if not p.startswith(("bound:", "unit:", "schedule:"))]
bounds = [b.rsplit(":", 4) for b in tagged("bound")]  # a column's name may hold a colon
units = dict(u.rsplit(":", 1) for u in tagged("unit"))
schedules = [s.rsplit(":", 2) for s in tagged("schedule")]
columns = []
for _, d in data:
    columns += [c for c in d if c != "t" and c not in columns]
for b in bounds:
    if b[0] not in columns:
        columns.append(b[0])
panels = len(columns) + len(schedules)
fig, axes = plt.subplots(panels, 1, figsize=(8, 2.2 * panels), sharex=True, squeeze=False)
for ax, column in zip(axes[:, 0], columns):
    ax.plot(fitted["t"], fitted[column], color="C0", lw=1.2, label="simulated with the estimates")
    for k, (path, d) in enumerate(data):
        if column in d:
            pts = [(t, y) for t, y in zip(d["t"], d[column]) if y is not None]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", ms=3, color="C%d" % (k + 1), label=path.split("/")[-1])
    for name, start, t, value, side in bounds:
        if name == column:
            label = "at least" if side == "least" else "at most"
            if float(start) < float(t):
                ax.plot([float(start), float(t)], [float(value)] * 2, "-", color="C3", lw=2, label=label)
            else:
                ax.plot([float(t)], [float(value)], "^" if side == "least" else "v", color="C3", ms=7, label=label)
    unit = units.get(column, "")
    ax.set_ylabel(column + (" (%s)" % unit if unit else ""))
    ax.grid(alpha=0.3)
for ax, (label, times, values) in zip(axes[len(columns):, 0], schedules):
    ts, vs = [float(x) for x in times.split(",")], [float(x) for x in values.split(",")]
    end = fitted["t"][-1]
    ax.plot([min(0.0, ts[0])] + ts + [max(end, ts[-1])], [vs[0]] + vs + [vs[-1]], "-", color="C4", lw=1.2)
    ax.plot(ts, vs, "o", ms=3, color="C4", label="fitted knots")
    ax.set_ylabel(label, fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
axes[0, 0].legend(fontsize=7, loc="best")
axes[-1, 0].set_xlabel("t (s)")
fig.tight_layout()
fig.savefig(out, dpi=110)
)PY";

std::string Joined(const std::vector<double>& numbers) {
  std::ostringstream text;
  text.precision(17);
  for (size_t k = 0; k < numbers.size(); ++k) text << (k ? "," : "") << numbers[k];
  return text.str();
}

// "schedule:LABEL:TIMES:VALUES" for every scheduled effect of the model (ScheduledEffects).
std::vector<std::string> ScheduleArguments(const Model<double>& model) {
  std::vector<std::string> args;
  for (const ScheduledEffect& effect : ScheduledEffects(model)) {
    args.push_back("schedule:" + effect.label + ":" + Joined(effect.times) + ":" + Joined(effect.values));
  }
  return args;
}

}  // namespace

std::vector<ScheduledEffect> ScheduledEffects(const Model<double>& model) {
  std::vector<ScheduledEffect> effects;
  for (const JointTorqueEffect<double>& motor : model.joint_torques) {
    if (motor.schedule.empty()) continue;
    const bool angle = motor.coordinate == JointCoordinate::kAngle;
    effects.push_back({"motor on " + model.joints[motor.joint].name + (angle ? " (N m)" : " (N)"), motor.schedule.times,
                       motor.schedule.values});
  }
  const auto components = [&](const Schedule<Vec3<double>>& schedule, const std::string& what, const char* unit) {
    for (int k = 0; k < 3; ++k) {
      std::vector<double> values;
      for (const Vec3<double>& v : schedule.values) values.push_back(v[k]);
      if (std::all_of(values.begin(), values.end(), [](double v) { return v == 0.0; })) continue;
      effects.push_back({what + ", " + "xyz"[k] + " (" + unit + ")", schedule.times, values});
    }
  };
  for (const ForceEffect<double>& force : model.forces) {
    if (!force.schedule.empty()) components(force.schedule, "force on " + model.bodies[force.body].name, "N");
  }
  for (const TorqueEffect<double>& torque : model.torques) {
    if (!torque.schedule.empty()) components(torque.schedule, "torque on " + model.bodies[torque.body].name, "N m");
  }
  return effects;
}

std::string ColumnUnit(const std::string& name) {
  if (name == "constraint_error") return "m";
  if (name == "energy") return "J";
  const std::string suffix = name.substr(name.rfind('.') + 1);
  if (suffix == "x" || suffix == "y" || suffix == "z" || suffix == "displacement") return "m";
  if (suffix == "vx" || suffix == "vy" || suffix == "vz" || suffix == "speed") return "m/s";
  if (suffix == "angle") return "rad";
  if (suffix == "omega" || suffix == "wx" || suffix == "wy" || suffix == "wz") return "rad/s";
  return "";  // a quaternion's components
}

void PlotFit(const Model<double>& fitted, const std::vector<Observations>& recordings,
             const std::vector<InequalityTarget>& constraints, const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path csv = fs::temp_directory_path() / ("tether-fitted-" + std::to_string(::getpid()) + ".csv");
  const std::string partial = path + ".partial" + fs::path(path).extension().string();
  const TemporaryPath csv_file(csv.string()), partial_file(partial);  // removed if the process is interrupted
  {
    std::ofstream out(csv);
    TrajectoryCsvWriter writer(fitted, &out);
    Simulate<double>(fitted, RunOptions{}, [&writer](const Sample<double>& s) { writer.Write(s); });
  }
  std::vector<std::string> args = {csv.string(), partial};
  for (const Observations& r : recordings) args.push_back(r.path);
  for (const TrajectoryColumn& column : TrajectoryColumns(fitted)) {
    const std::string unit = ColumnUnit(column.name);
    if (!unit.empty()) args.push_back("unit:" + column.name + ":" + unit);
  }
  for (const std::string& schedule : ScheduleArguments(fitted)) args.push_back(schedule);
  for (const InequalityTarget& c : constraints) {
    std::ostringstream bound;
    bound.precision(17);
    bound << "bound:" << c.column << ":" << c.from << ":" << c.time << ":" << c.value << ":"
          << (c.at_least ? "least" : "most");
    args.push_back(bound.str());
  }
  try {
    RunMatplotlib(kScript, args, "--plot");
  } catch (...) {
    fs::remove(csv);
    fs::remove(partial);
    throw;
  }
  fs::remove(csv);
  fs::rename(partial, path);
}

}  // namespace tether::cli
