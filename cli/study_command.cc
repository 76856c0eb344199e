#include "study_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "matplotlib_script.h"
#include "study_figures_script.h"
#include "tether/dynamics/errors.h"
#include "tether/studies/gain_map.h"
#include "tether/studies/study.h"
#include "tether/studies/study_mpi.h"

namespace tether::cli {
namespace {

void WriteSummary(const StudySpec& spec, const std::vector<StudyRow>& rows, const std::string& folder) {
  std::ofstream out(std::filesystem::path(folder) / "summary.md");
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
    out << ".\n";
  }
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

void ShowProgress(int done, int total, double seconds_left) {
  const int width = 30, filled = total ? width * done / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d runs, about %.0f s left   ", std::string(filled, '#').c_str(),
               std::string(width - filled, '.').c_str(), done, total, seconds_left);
  if (done == total) std::fprintf(stderr, "\n");
}

class StudyCommand final : public Command {
 public:
  explicit StudyCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("study", "run a study: a scene over swept values, with metrics and figures");
    app_->add_option("STUDY", study_path_, "study file (JSON): scene, sweep, metrics")->required();
    app_->add_option("--out", folder_, "output folder (results.csv, figures, summary.md)")->required();
    threads_option_ = app_->add_option("--threads", threads_,
                                       "parallel runs (default: all cores; under mpirun, the cores per rank)");
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    if (threads_option_->count() > 0 && threads_ < 1) {
      throw InputError("--threads: must be a whole number >= 1, got " + std::to_string(threads_));
    }
    if (LaunchedByMpirun()) return RunOverMpi();
    const StudySpec spec = ReadStudySpec(study_path_);
    Finish(spec, RunStudy(spec, folder_, threads_option_->count() > 0 ? threads_ : AllCores(), ShowProgress));
    return 0;
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
    } catch (const InputError&) {
      if (session.rank() == 0) throw;
      return 2;
    }
    const int threads = threads_option_->count() > 0 ? threads_ : session.threads_per_rank();
    const std::vector<StudyRow> rows = RunStudyOverMpi(session, spec, folder_, threads, ShowProgress);
    if (session.rank() == 0) Finish(spec, rows);
    return 0;
  }

  void Finish(const StudySpec& spec, const std::vector<StudyRow>& rows) const {
    DrawFigures(spec, folder_);
    WriteSummary(spec, rows, folder_);
    std::cerr << "tether: wrote " << (std::filesystem::path(folder_) / "results.csv").string()
              << ", the figures and summary.md in " << folder_ << "\n";
  }

  CLI::App* app_;
  CLI::Option* threads_option_;
  std::string study_path_, folder_;
  int threads_ = 0;
};

}  // namespace

std::unique_ptr<Command> MakeStudyCommand(CLI::App* parent) { return std::make_unique<StudyCommand>(parent); }

}  // namespace tether::cli
