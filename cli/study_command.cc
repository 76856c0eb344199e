#include "study_command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "flags.h"
#include "matplotlib_script.h"
#include "study_figures_script.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/studies/gain_map.h"
#include "tether/studies/study.h"
#include "tether/studies/study_mpi.h"
#ifdef TETHER_HAVE_VIEWER
#include "study_index.h"
#endif

namespace tether::cli {
namespace {

// Whether smaller is better for a metric, and whether ranking rows by it says something: the gains a row ran
// with are settings, not results, the events a run had are neither better nor worse, and energy drift measures error
// only where the scene conserves energy.
bool Ranked(const StudySpec& spec, const std::string& metric) {
  if (metric == "alpha" || metric == "beta" || metric == "events") return false;
  if (metric != "energy_drift") return true;
  for (const nlohmann::json& scene : spec.scenes) {
    if (!ConservesEnergy(ParseScene(scene, spec.path).model)) return false;
  }
  return true;
}

void WriteSummary(const StudySpec& spec, const std::vector<StudyRow>& rows, const std::string& folder) {
  AtomicOutputFile file((std::filesystem::path(folder) / "summary.md").string());
  std::ostream& out = file.stream();
  out << "# Study " << spec.path << "\n\nScene" << (spec.scene_paths.size() > 1 ? "s:" : ":");
  for (size_t k = 0; k < spec.scene_paths.size(); ++k) {
    out << (k ? ", `" : " `") << spec.scene_paths[k] << "`";
    if (!spec.scene_labels.empty()) out << " (" << spec.scene_labels[k] << ")";
  }
  out << "; " << rows.size() << " runs over the sweep of";
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
    for (const nlohmann::json& v : row.values) out << " " << CellText(v) << " |";
    for (double m : row.metrics) {
      std::snprintf(number, sizeof number, "%.3g", m);
      out << " " << number << " |";
    }
    out << " " << row.status.substr(0, row.status.find(':')) << " |\n";
  }
  out << "\n";
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    if (!Ranked(spec, spec.metrics[m])) continue;
    // a run that reproduces the reference exactly (an RMS error of 0) is the reference itself, not a winner
    const bool reference_excluded = spec.metrics[m] == "rms_position_error";
    const StudyRow* best = nullptr;
    for (const StudyRow& row : rows) {
      const double value = row.metrics[m];
      if (row.status != "ok" || std::isnan(value) || (reference_excluded && value == 0.0)) continue;
      if (!best || value < best->metrics[m]) best = &row;
    }
    if (!best) continue;
    out << "- Smallest " << spec.metrics[m] << ": " << best->metrics[m] << " at";
    for (size_t k = 0; k < spec.pointers.size(); ++k) out << " " << spec.pointers[k] << " = " << best->values[k].dump();
    out << (reference_excluded ? " (runs identical to the reference left out)" : "") << ".\n";
  }
  file.Commit();
}

// Draws the study's figures into `folder` (study_figures.py); gain maps first get their marks, written to
// folder/gain_map_marks.json.
void DrawFigures(const StudySpec& spec, const std::string& folder) {
  namespace fs = std::filesystem;
  std::vector<std::string> args = {(fs::path(folder) / "results.csv").string(), folder,
                                   std::to_string(spec.pointers.size()), nlohmann::json(spec.figures).dump()};
  for (const nlohmann::json& figure : spec.figures) {
    if (figure["type"] != "gain_map") continue;
    std::cerr << "tether: tuning the gains of each gain map panel\n";
    args.push_back((fs::path(folder) / "gain_map_marks.json").string());
    std::ofstream(args.back()) << GainMapMarks(spec).dump(1) << "\n";
    break;
  }
  RunMatplotlib(kStudyFiguresScript, args, "study");
}

// The progress bar on a terminal, redrawn in place; elsewhere (a log file, CI) a plain line at every tenth of
// the rows, without carriage returns.
void ShowProgress(int done, int total, double seconds_left) {
  static const bool terminal = ::isatty(STDERR_FILENO) != 0;
  if (terminal) {
    const int width = 30, filled = total ? width * done / total : width;
    std::fprintf(stderr, "\r[%s%s] %d/%d runs, about %.0f s left   ", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total, seconds_left);
    if (done == total) std::fprintf(stderr, "\n");
    return;
  }
  const int tenth = std::max(1, total / 10);
  if (done % tenth == 0 || done == total) {
    std::fprintf(stderr, "tether: %d/%d runs, about %.0f s left\n", done, total, seconds_left);
  }
}

void NoProgress(int, int, double) {}

class StudyCommand final : public Command {
 public:
  explicit StudyCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("study", "run a study: a scene over swept values, with metrics and figures");
    app_->add_option("STUDY", study_path_, "study file (JSON): scene, sweep, metrics")->required();
    app_->add_option("--out", folder_, "output folder (results.csv, figures, summary.md)")->required();
    threads_option_ = app_->add_option("--threads", threads_,
                                       "parallel runs (default: all cores; under mpirun, the cores per rank)");
    app_->add_flag("--restart", restart_, "discard the partial or finished results of an earlier study in --out");
    app_->add_flag("--quiet", quiet_, "no progress on stderr");
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    if (threads_option_->count() > 0) CheckCount(threads_, 1, kMaxThreads, "--threads");
    if (LaunchedByMpirun()) return RunOverMpi();
    const StudySpec spec = ReadStudySpec(study_path_);
    std::vector<StudyRow> rows;
    try {
      const CatchInterrupts catching;  // Ctrl-C stops between rows and keeps what is done
      rows = RunStudy(spec, folder_, threads_option_->count() > 0 ? threads_ : AllCores(), restart_, Progress(),
                      RowViews());
    } catch (const StudyInterrupted& e) {
      std::cerr << "\ntether: study interrupted (signal " << e.signal() << "); the finished rows are in "
                << (std::filesystem::path(folder_) / "results.partial.csv").string()
                << ", and the same command resumes the study\n";
      return 128 + e.signal();
    }
    return Finish(spec, rows);
  }

 private:
  static int AllCores() { return std::max(1u, std::thread::hardware_concurrency()); }

  // Every rank reads the study; rank 0 alone reports a bad one (the others would repeat its message), runs its
  // share, collects the rows and draws.
  int RunOverMpi() {
    const MpiSession session;
    StudySpec spec;
    try {
      spec = ReadStudySpec(study_path_);
    } catch (const InputError& e) {
      // rank 0 reports before MPI_Finalize (the session's end): the other ranks return at once, and once one has
      // exited with status 2 mpirun may stop rank 0 before a message printed after its MPI_Finalize
      if (session.rank() == 0) std::cerr << "tether: error: " << e.what() << std::endl;
      return 2;
    }
    const int threads = threads_option_->count() > 0 ? threads_ : session.threads_per_rank();
    const std::vector<StudyRow> rows =
        RunStudyOverMpi(session, spec, folder_, threads, restart_, Progress(), RowViews());
    return session.rank() == 0 ? Finish(spec, rows) : 0;
  }

  StudyProgress Progress() const { return quiet_ ? StudyProgress(NoProgress) : StudyProgress(ShowProgress); }

  // Each row's motion for index.html (none without the viewer).
  RowMotion RowViews() const {
#ifdef TETHER_HAVE_VIEWER
    return RowViewWriter(folder_);
#else
    return {};
#endif
  }

  // results.csv is complete by now: the summary and the figures follow, and a failure to draw (no matplotlib)
  // is reported (exit status 1) without losing anything computed.
  int Finish(const StudySpec& spec, const std::vector<StudyRow>& rows) const {
    const std::string results = (std::filesystem::path(folder_) / "results.csv").string();
    WriteSummary(spec, rows, folder_);
    std::string drawing_failed;
    try {
      DrawFigures(spec, folder_);
    } catch (const InputError& e) {
      drawing_failed = e.what();
    }
#ifdef TETHER_HAVE_VIEWER
    WriteStudyIndex(spec, rows, folder_);  // with the figures there are
    const char* index = ", index.html";
#else
    const char* index = "";
#endif
    if (!drawing_failed.empty()) {
      std::cerr << "tether: error: " << drawing_failed << "\ntether: " << results << index
                << " and summary.md are complete; only the figures are missing (run the same command again to draw "
                   "them)\n";
      return 1;
    }
    std::cerr << "tether: wrote " << results << ", the figures" << index << " and summary.md in " << folder_ << "\n";
    return 0;
  }

  CLI::App* app_;
  CLI::Option* threads_option_;
  std::string study_path_, folder_;
  int threads_ = 0;
  bool restart_ = false, quiet_ = false;
};

}  // namespace

std::unique_ptr<Command> MakeStudyCommand(CLI::App* parent) { return std::make_unique<StudyCommand>(parent); }

}  // namespace tether::cli
