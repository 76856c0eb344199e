#include "fit_plot.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "matplotlib_script.h"
#include "tether/dynamics/errors.h"
#include "tether/dynamics/interrupts.h"
#include "tether/dynamics/simulator.h"
#include "tether/dynamics/trajectory_csv.h"

namespace tether::cli {
namespace {

// argv: fitted.csv output.png [data.csv ...] [bound:COLUMN:FROM:T:VALUE:least|most ...] (FROM = T: at T)
constexpr const char* kScript = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k.strip(): [float(r[k]) if r[k].strip() else None for r in rows] for k in rows[0]}

fitted, out = read(sys.argv[1]), sys.argv[2]
data = [(p, read(p)) for p in sys.argv[3:] if not p.startswith("bound:")]
bounds = [b.split(":")[1:] for b in sys.argv[3:] if b.startswith("bound:")]
columns = []
for _, d in data:
    columns += [c for c in d if c != "t" and c not in columns]
for b in bounds:
    if b[0] not in columns:
        columns.append(b[0])
fig, axes = plt.subplots(len(columns), 1, figsize=(8, 2.2 * len(columns)), sharex=True, squeeze=False)
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
    ax.set_ylabel(column)
    ax.grid(alpha=0.3)
axes[0, 0].legend(fontsize=7, loc="best")
axes[-1, 0].set_xlabel("t (s)")
fig.tight_layout()
fig.savefig(out, dpi=110)
)PY";

}  // namespace

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
