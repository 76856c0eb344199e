#include "tune_command.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "flags.h"
#include "progress_line.h"
#include "scene_overrides.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/reports.h"

namespace tether::cli {
namespace {

void PrintSummary(const TuneResult& r, double step) {
  std::fprintf(stderr, "tuned: alpha %.6g, beta %.6g (omega %.6g rad/s, zeta %.4g), objective %.4g m\n", r.alpha,
               r.beta, r.omega, r.zeta, r.objective);
  std::fprintf(stderr, "stability: h omega = %.4g, bound %.4g, margin %.0f%%; %d evaluations in %.2f s (%s)\n",
               step * r.omega, r.bound, 100.0 * r.margin, r.optimizer.evaluations, r.optimizer.seconds,
               r.optimizer.message.c_str());
  std::fprintf(stderr, "%-13s %10s %10s %12s %14s %14s %12s %9s\n", "gains", "alpha", "beta", "objective",
               "rms error (m)", "max C (m)", "energy drift", "time (s)");
  for (const GainMetrics& m : r.comparison) {
    if (m.diverged) {
      std::fprintf(stderr, "%-13s %10.4g %10.4g %12.4g %14s\n", m.name.c_str(), m.alpha, m.beta, m.objective,
                   "diverges");
    } else {
      std::fprintf(stderr, "%-13s %10.4g %10.4g %12.4g %14.3e %14.3e %12.3e %9.3f\n", m.name.c_str(), m.alpha,
                   m.beta, m.objective, m.rms_position_error, m.max_constraint_error, m.energy_drift, m.seconds);
    }
  }
}

class TuneCommand final : public Command {
 public:
  explicit TuneCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("tune", "tune the Baumgarte gains for the scene's integrator and step");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    app_->add_option("--objective", objective_, "reference (default: error against an accurate reference) or drift");
    app_->add_option("--optimizer", optimizer_, "ceres (default) or nlopt:ALGORITHM (NLopt's name, e.g. nlopt:LN_BOBYQA)");
    app_->add_option("--samples", samples_, "number of initial states (the scene's and perturbed ones; default 1)");
    app_->add_option("--max-evaluations", max_evaluations_, "budget of objective evaluations for NLopt; Ceres gets half as many iterations (default 200)");
    app_->add_flag("--quiet", quiet_, "no progress on stderr");
    app_->add_option("-o,--output,--write-scene", write_scene_, "write the scene with the tuned gains here");
    overrides_.Register(app_, false);  // the gains and the method are what it tunes
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    TuneSettings settings;
    if (objective_ == "reference") {
      settings.objective.kind = GainObjectiveKind::kReference;
    } else if (objective_ == "drift") {
      settings.objective.kind = GainObjectiveKind::kDrift;
    } else {
      throw InputError("--objective: unknown objective '" + objective_ + "' (expected reference or drift)");
    }
    CheckCount(samples_, 1, kMaxSamples, "--samples");
    CheckCount(max_evaluations_, 2, kMaxEvaluations, "--max-evaluations");
    CheckOutputs({{write_scene_, "-o/--write-scene"}}, {scene_path_});
    settings.objective.samples = samples_;
    settings.optimizer.name = optimizer_;
    settings.optimizer.max_evaluations = max_evaluations_;
    CheckOptimizerName(optimizer_, "--optimizer");
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    std::unique_ptr<AtomicOutputFile> out;
    if (!write_scene_.empty()) out = std::make_unique<AtomicOutputFile>(write_scene_);

    TuneResult result;
    {
      ProgressLine progress("tune", quiet_);
      settings.optimizer.observer = progress.Observer();
      try {
        result = TuneGains(scene.model, settings);
      } catch (const InputError& e) {
        throw InputError(scene_path_ + ": " + e.what());
      } catch (const SimulationDiverged& e) {
        throw SimulationDiverged(scene_path_ + ": the reference motion diverged: " + e.what(), e.time(),
                                 e.constraint());
      }
    }
    const bool failed = !std::isfinite(result.objective);  // the optimizer's runs failed: nothing was tuned
    if (out && !failed) {
      nlohmann::json tuned = scene.document;
      tuned["stabilization"] = {{"method", "baumgarte"}, {"alpha", result.alpha}, {"beta", result.beta}};
      out->stream() << tuned.dump(2) << "\n";
      out->Commit();
    }
    PrintSummary(result, scene.model.simulation.step);
    std::cout << TuneJson(result, objective_, optimizer_, scene.model.simulation.step).dump(2) << std::endl;
    if (failed) {
      std::cerr << "tether: tune failed: the tuned gains give no finite objective (their runs diverged)"
                << (out ? "; no scene was written" : "") << "\n";
      return 1;
    }
    return 0;
  }

 private:
  CLI::App* app_;
  std::string scene_path_, objective_ = "reference", optimizer_ = "ceres", write_scene_;
  int samples_ = 1, max_evaluations_ = 200;
  bool quiet_ = false;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeTuneCommand(CLI::App* parent) { return std::make_unique<TuneCommand>(parent); }

}  // namespace tether::cli
