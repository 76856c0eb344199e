#include "study_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "matplotlib_script.h"
#include "tether/dynamics/errors.h"
#include "tether/studies/study.h"

namespace tether::cli {
namespace {

// argv: results.csv folder n_pointers; one figure per metric: the metric against the first swept pointer, one
// line per combination of the other pointers that take several values (log axes when values span decades;
// diverged runs and, on a log axis, exact zeros are left out).
constexpr const char* kPlotScript = R"PY(
import csv, math, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

path, folder, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
with open(path) as f:
    reader = csv.reader(f)
    header = next(reader)
    rows = list(reader)
pointers, metrics = header[:n], header[n:-1]

def number(text):
    try:
        value = float(text)
        return None if math.isnan(value) else value
    except ValueError:
        return None

def short(pointer):
    return pointer.rsplit("/", 1)[-1]

# pointers with several values label the lines; the first one is the x axis
varying = [k for k in range(1, n) if len({r[k] for r in rows}) > 1]
x_numeric = all(number(r[0]) is not None for r in rows)
for m, metric in enumerate(metrics):
    values = [v for v in (number(r[n + m]) for r in rows) if v is not None]
    positive = [v for v in values if v > 0]
    log = len(positive) > 1 and max(positive) / min(positive) > 100
    fig, ax = plt.subplots(figsize=(8.0, 4.4))
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in varying), []).append(r)
    for key, members in groups.items():
        pts = [(number(r[0]) if x_numeric else r[0], number(r[n + m])) for r in members]
        pts = [(x, y) for x, y in pts if y is not None and (y > 0 or not log)]
        label = ", ".join("%s=%s" % (short(pointers[k]), v) for k, v in zip(varying, key)) or metric
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=4, label=label)
    if log:
        ax.set_yscale("log")
    if x_numeric and all(number(r[0]) > 0 for r in rows):
        ax.set_xscale("log")
    ax.set_xlabel(pointers[0])
    ax.set_ylabel(metric)
    ax.grid(alpha=0.3, which="both")
    if len(groups) > 1:
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(folder, "%s.%s" % (metric, ext)), dpi=110)
    plt.close(fig)
)PY";

void WriteSummary(const StudySpec& spec, const std::vector<StudyRow>& rows, const std::string& folder) {
  std::ofstream out(std::filesystem::path(folder) / "summary.md");
  out << "# Study " << spec.path << "\n\nScene: `" << spec.scene_path << "`; " << rows.size()
      << " runs over the sweep of";
  for (const std::string& p : spec.pointers) out << " `" << p << "`";
  out << ".\n\n|";
  for (const std::string& p : spec.pointers) out << " " << p << " |";
  for (const std::string& m : spec.metrics) out << " " << m << " |";
  out << " status |\n|";
  for (size_t k = 0; k < spec.pointers.size() + spec.metrics.size() + 1; ++k) out << "---|";
  out << "\n";
  char number[32];
  for (const StudyRow& row : rows) {
    out << "|";
    for (const nlohmann::json& v : row.values) out << " " << (v.is_string() ? v.get<std::string>() : v.dump()) << " |";
    for (double m : row.metrics) {
      std::snprintf(number, sizeof number, "%.3g", m);
      out << " " << number << " |";
    }
    out << " " << (row.status == "ok" ? "ok" : "diverged") << " |\n";
  }
  out << "\n";
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    const StudyRow* best = nullptr;
    for (const StudyRow& row : rows) {
      if (!std::isnan(row.metrics[m]) && (!best || row.metrics[m] < best->metrics[m])) best = &row;
    }
    if (!best) continue;
    out << "- Smallest " << spec.metrics[m] << ": " << best->metrics[m] << " at";
    for (size_t k = 0; k < spec.pointers.size(); ++k) out << " " << spec.pointers[k] << " = " << best->values[k].dump();
    out << ". Figure: `" << spec.metrics[m] << ".png`.\n";
  }
}

class StudyCommand final : public Command {
 public:
  explicit StudyCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("study", "run a study: a scene over swept values, with metrics and figures");
    app_->add_option("STUDY", study_path_, "study file (JSON): scene, sweep, metrics")->required();
    app_->add_option("--out", folder_, "output folder (results.csv, figures, summary.md)")->required();
    app_->add_option("--threads", threads_, "parallel runs (default: all cores)");
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    if (threads_ < 1) throw InputError("--threads: must be a whole number >= 1, got " + std::to_string(threads_));
    const StudySpec spec = ReadStudySpec(study_path_);
    const std::vector<StudyRow> rows = RunStudy(spec, folder_, threads_, [](int done, int total, double left) {
      const int width = 30, filled = total ? width * done / total : width;
      std::fprintf(stderr, "\r[%s%s] %d/%d runs, about %.0f s left   ", std::string(filled, '#').c_str(),
                   std::string(width - filled, '.').c_str(), done, total, left);
      if (done == total) std::fprintf(stderr, "\n");
    });
    const std::string results = (std::filesystem::path(folder_) / "results.csv").string();
    RunMatplotlib(kPlotScript, {results, folder_, std::to_string(spec.pointers.size())}, "study");
    WriteSummary(spec, rows, folder_);
    std::cerr << "tether: wrote " << results << ", one figure per metric and summary.md in " << folder_ << "\n";
    return 0;
  }

 private:
  CLI::App* app_;
  std::string study_path_, folder_;
  int threads_ = std::max(1u, std::thread::hardware_concurrency());
};

}  // namespace

std::unique_ptr<Command> MakeStudyCommand(CLI::App* parent) { return std::make_unique<StudyCommand>(parent); }

}  // namespace tether::cli
