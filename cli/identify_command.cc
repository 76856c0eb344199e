#include "identify_command.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "fit_plot.h"
#ifdef TETHER_HAVE_VIEWER
#include "fit_report.h"
#endif
#include "flags.h"
#include "progress_line.h"
#include "scene_overrides.h"
#include "scene_run.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/identify.h"
#include "tether/tuning/reports.h"

namespace tether::cli {
namespace {

// "PTR=LO:HI" -> (PTR, LO, HI); either bound may be empty (unbounded on that side).
std::tuple<std::string, double, double> ParseBound(const std::string& text) {
  const size_t equals = text.rfind('='), colon = text.rfind(':');
  if (equals == std::string::npos || colon == std::string::npos || colon < equals) {
    throw InputError("--bound: '" + text + "' is not PTR=LO:HI (e.g. /bodies/0/mass=0.1:10)");
  }
  auto number = [&text](const std::string& s, double unbounded) {
    if (s.empty()) return unbounded;
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || std::isnan(x)) throw InputError("--bound: '" + text + "': '" + s + "' is not a number");
    return x;
  };
  const double lo = number(text.substr(equals + 1, colon - equals - 1), -std::numeric_limits<double>::max());
  const double hi = number(text.substr(colon + 1), std::numeric_limits<double>::max());
  if (!(lo < hi)) throw InputError("--bound: '" + text + "': LO must be below HI");
  return {text.substr(0, equals), lo, hi};
}

class IdentifyCommand final : public Command {
 public:
  IdentifyCommand(CLI::App* parent, bool fit) : fit_(fit) {
    app_ = fit ? parent->add_subcommand("fit", "fit initial conditions or force schedules to target keyframes")
               : parent->add_subcommand("identify", "identify scene parameters from recorded trajectories");
    app_->add_option("SCENE", scene_path_, "scene file (JSON) holding the initial guess")->required();
    CLI::Option* data =
        app_->add_option("--data", data_paths_, "a recording or targets: trajectory CSV with t and any columns (repeatable)");
    if (!fit) data->required();
    app_->add_option("--param", pointers_, "an unknown, as a JSON Pointer into the scene (repeatable)")->required();
    app_->add_option("--bound", bounds_, "PTR=LO:HI bounds an unknown (repeatable; LO or HI may be left empty)");
    app_->add_option("--tie", ties_, "PTR=EXPR: PTR follows EXPR of other scene numbers in braces (repeatable)");
    app_->add_option("--segments", segments_,
                     fit ? "multiple shooting with K segments (default: single shooting, multiple where it fails)"
                         : "multiple shooting with K segments (default 1: single shooting)");
    app_->add_option("--loss", loss_, "robust loss: huber:DELTA or cauchy:DELTA (default: squares)");
    app_->add_option("--optimizer", optimizer_, "ceres (default) or nlopt:ALGORITHM");
    app_->add_option("--method", method_,
                     "derivatives for a gradient-based NLopt algorithm: auto (default: the adjoint from " +
                         std::to_string(kAdjointCrossover) + " unknowns on), jet or adjoint");
    app_->add_option("--max-evaluations", max_evaluations_, "budget of residual evaluations for NLopt; Ceres gets half as many iterations (default 200; 1000 for a fit with constraints or starts)");
    app_->add_option("-o,--output", output_path_, "write the scene with the estimates in place");
    app_->add_option("--plot", plot_path_, "draw the data against the motion with the estimates (PNG or SVG)");
    app_->add_option("--report", report_path_,
                     "write an HTML report: the fit per column, residuals, parameters, correlations, the motion");
    app_->add_flag("--quiet", quiet_, "no progress on stderr");
    if (fit) {
      app_->add_option("--smooth", smooth_, "weight W of the penalty on changes between schedule values");
      app_->add_option("--effort", effort_, "weight W of the joint motors' effort, W times the integral of torque^2");
      app_->add_option("--at-least", at_least_, "COLUMN=VALUE@T: a constraint, COLUMN >= VALUE at time T; COLUMN=VALUE@T0:T1: at every step from T0 to T1 (repeatable)");
      app_->add_option("--at-most", at_most_, "COLUMN=VALUE@T: a constraint, COLUMN <= VALUE at time T; COLUMN=VALUE@T0:T1: at every step from T0 to T1 (repeatable)");
      app_->add_option("--starts", starts_, "the scene's values and N - 1 random starts within the bounds (default 1)");
      app_->add_option("--seed", seed_, "seed of the random starts (default 1)");
    }
    overrides_.Register(app_);
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    IdentifySettings settings;
    settings.optimizer.name = optimizer_;
    CheckOptimizerName(optimizer_, "--optimizer");
    settings.method = ParseGradientMethod(method_, "--method");
    for (const std::string& text : at_least_) settings.inequalities.push_back(ParseInequality(text, true, "--at-least"));
    for (const std::string& text : at_most_) settings.inequalities.push_back(ParseInequality(text, false, "--at-most"));
    CheckCount(starts_, 1, kMaxStarts, "--starts");
    settings.starts = starts_;
    settings.seed = seed_;
    const bool trajectory = !settings.inequalities.empty() || starts_ > 1;
    // constraints need a solver made for them (identification.h); an explicit --optimizer is taken as given
    if (trajectory && app_->count("--optimizer") == 0) settings.optimizer.name = optimizer_ = kTrajectoryOptimizer;
    if (trajectory && app_->count("--max-evaluations") == 0) max_evaluations_ = kTrajectoryMaxEvaluations;
    if (data_paths_.empty() && settings.inequalities.empty()) {
      throw InputError("--data: fit needs targets: --data TARGETS.csv, or constraints (--at-least, --at-most)");
    }
    if (!(effort_ >= 0) || !std::isfinite(effort_)) throw InputError("--effort: must be >= 0");
    settings.effort = effort_;
    if (!loss_.empty()) settings.optimizer.loss = ParseRobustLoss(loss_, "--loss");
    CheckCount(segments_, 1, kMaxSegments, "--segments");
    CheckCount(max_evaluations_, 2, kMaxEvaluations, "--max-evaluations");
    std::vector<std::string> inputs = data_paths_;
    inputs.push_back(scene_path_);
    CheckOutputs({{output_path_, "-o"}, {plot_path_, "--plot", true}, {report_path_, "--report"}}, inputs);
#ifndef TETHER_HAVE_VIEWER
    if (!report_path_.empty()) {
      throw InputError(
          "--report: this tether was built without the viewer (-DTETHER_VIEWER=OFF): install libjs-three and "
          "configure with -DTETHER_VIEWER=ON");
    }
#endif
    if (!(smooth_ >= 0) || !std::isfinite(smooth_)) throw InputError("--smooth: must be >= 0");
    settings.segments = fit_ && app_->count("--segments") == 0 ? 0 : segments_;
    settings.smooth = smooth_;
    settings.optimizer.max_evaluations = max_evaluations_;

    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    ParameterSet parameters(scene, pointers_);
    parameters.Tie(scene, ties_);
    std::vector<ParameterBound> bounds;
    for (const std::string& text : bounds_) {
      const auto [pointer, lo, hi] = ParseBound(text);
      bounds.push_back({pointer, lo, hi});
    }
    settings.bounds = BoundsFor(parameters, bounds, "--bound");
    std::vector<Observations> recordings;
    for (const std::string& path : data_paths_) recordings.push_back(ReadObservations(path, scene.model));
    std::unique_ptr<AtomicOutputFile> out;
    if (!output_path_.empty()) out = std::make_unique<AtomicOutputFile>(output_path_);

    IdentifyResult result;
    {
      ProgressLine progress(fit_ ? "fit" : "identify", quiet_);
      settings.optimizer.observer = progress.Observer();
      try {
        result = Identify(scene.model, parameters, recordings, settings);
      } catch (const InputError& e) {
        throw InputError(scene_path_ + ": " + e.what());
      }
      settings.optimizer.observer = nullptr;
    }
    if (out && !result.failed) {  // a failed fit writes no scene (its JSON says why)
      try {
        out->stream() << parameters.SceneWith(scene, result.estimate).document.dump(2) << "\n";
        out->Commit();
      } catch (const InputError& e) {  // an estimate outside the format's domain (no bound kept it in)
        result.failed = true;
        result.warnings.push_back(std::string("the estimate makes a scene the format refuses: ") + e.what());
      }
    }
    std::cout << IdentifyJson(parameters, result, optimizer_).dump(2) << std::endl;
    for (const std::string& warning : result.warnings) std::cerr << "tether: warning: " << warning << "\n";
    if (result.failed) {
      std::cerr << "tether: the " << (fit_ ? "fit" : "identification") << " failed (warnings above)"
                << (out ? "; no scene was written" : "") << "\n";
    }
    // last: a plot or a report that fails loses nothing computed
    Model<double> fitted = scene.model;
    parameters.Assign(result.estimate, &fitted);
    if (!plot_path_.empty()) {
      try {
        PlotFit(fitted, recordings, settings.inequalities, plot_path_);
      } catch (const InputError& e) {
        std::cerr << "tether: error: " << e.what() << "\ntether: the results above are complete; only the plot is missing\n";
        return 1;
      }
    }
#ifdef TETHER_HAVE_VIEWER
    if (!report_path_.empty()) {
      try {
        AtomicOutputFile report(report_path_);
        report.stream() << NamingScene(scene_path_, [&] {
          return FitReportHtml(
              {fit_, scene_path_, optimizer_, &fitted, &parameters, &result, &recordings, &settings.inequalities});
        });
        report.Commit();
      } catch (const std::exception& e) {
        std::cerr << "tether: error: --report: " << e.what()
                  << "\ntether: the results above are complete; only the report is missing\n";
        return 1;
      }
    }
#endif
    return result.failed ? 1 : 0;
  }

 private:
  bool fit_;
  bool quiet_ = false;
  CLI::App* app_;
  std::string scene_path_, output_path_, plot_path_, report_path_, loss_, optimizer_ = "ceres", method_ = "auto";
  std::vector<std::string> data_paths_, pointers_, bounds_, ties_;
  std::vector<std::string> at_least_, at_most_;
  int segments_ = 1, max_evaluations_ = 200, starts_ = 1;
  unsigned seed_ = 1;
  double smooth_ = 0.0, effort_ = 0.0;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeIdentifyCommand(CLI::App* parent) { return std::make_unique<IdentifyCommand>(parent, false); }
std::unique_ptr<Command> MakeFitCommand(CLI::App* parent) { return std::make_unique<IdentifyCommand>(parent, true); }

}  // namespace tether::cli
