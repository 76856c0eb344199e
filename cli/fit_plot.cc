#include "fit_plot.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tether/dynamics/errors.h"
#include "tether/dynamics/simulator.h"
#include "tether/dynamics/trajectory_csv.h"

namespace tether::cli {
namespace {

// argv: fitted.csv output.png data.csv [data.csv ...]
constexpr const char* kScript = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k.strip(): [float(r[k]) if r[k].strip() else None for r in rows] for k in rows[0]}

fitted, out, data = read(sys.argv[1]), sys.argv[2], [(p, read(p)) for p in sys.argv[3:]]
columns = []
for _, d in data:
    columns += [c for c in d if c != "t" and c not in columns]
fig, axes = plt.subplots(len(columns), 1, figsize=(8, 2.2 * len(columns)), sharex=True, squeeze=False)
for ax, column in zip(axes[:, 0], columns):
    ax.plot(fitted["t"], fitted[column], color="C0", lw=1.2, label="simulated with the estimates")
    for k, (path, d) in enumerate(data):
        if column in d:
            pts = [(t, y) for t, y in zip(d["t"], d[column]) if y is not None]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", ms=3, color="C%d" % (k + 1), label=path.split("/")[-1])
    ax.set_ylabel(column)
    ax.grid(alpha=0.3)
axes[0, 0].legend(fontsize=7, loc="best")
axes[-1, 0].set_xlabel("t (s)")
fig.tight_layout()
fig.savefig(out, dpi=110)
)PY";

std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void PlotFit(const Model<double>& fitted, const std::vector<Observations>& recordings, const std::string& path) {
  namespace fs = std::filesystem;
  char pattern[] = "/tmp/tether-plot-XXXXXX";
  if (!mkdtemp(pattern)) throw InputError("--plot: cannot make a temporary folder");
  const fs::path work(pattern);
  const std::string script = (work / "plot_fit.py").string(), csv = (work / "fitted.csv").string();
  std::ofstream(script) << kScript;
  {
    std::ofstream out(csv);
    TrajectoryCsvWriter writer(fitted, &out);
    Simulate<double>(fitted, RunOptions{}, [&writer](const Sample<double>& s) { writer.Write(s); });
  }
  const std::string extension = fs::path(path).extension().string();
  const std::string partial = path + ".partial" + extension;
  const char* python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string command = std::string(python) + " " + Quote(script) + " " + Quote(csv) + " " + Quote(partial);
  for (const Observations& r : recordings) command += " " + Quote(r.path);
  command += " 2>" + Quote((work / "errors.txt").string());
  const int status = std::system(command.c_str());
  std::string errors;
  std::getline(std::ifstream(work / "errors.txt"), errors, '\0');
  fs::remove_all(work);
  if (status != 0 || !fs::exists(partial)) {
    fs::remove(partial);
    throw InputError("--plot: drawing failed (python3 with matplotlib is needed: apt-get install python3-matplotlib)" +
                     (errors.empty() ? std::string() : ": " + errors.substr(errors.rfind('\n', errors.size() - 2) + 1)));
  }
  fs::rename(partial, path);
}

}  // namespace tether::cli
