#include "gradient_command.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include "scene_overrides.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/errors.h"

namespace tether::cli {
namespace {

class GradientCommand final : public Command {
 public:
  explicit GradientCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("gradient", "loss against observations and its gradient with respect to parameters");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    app_->add_option("--data", data_path_, "observations: a trajectory CSV with t and any subset of columns")->required();
    app_->add_option("--param", pointers_, "a parameter, as a JSON Pointer into the scene (repeatable)")->required();
    app_->add_option("--method", method_,
                     "adjoint (the discrete adjoint), jet (Jets through the KKT solves) or fd (central differences)");
    overrides_.Register(app_);
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    if (method_ != "jet" && method_ != "fd" && method_ != "adjoint") {
      throw InputError("--method: unknown method '" + method_ + "' (expected adjoint, jet or fd)");
    }
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    const ParameterSet parameters(scene, pointers_);
    const Observations observations = ReadObservations(data_path_, scene.model);

    const auto start = std::chrono::steady_clock::now();
    LossGradient result;
    try {
      if (method_ == "jet") {
        result = JetLossGradient(scene.model, parameters, observations);
      } else if (method_ == "adjoint") {
        result = AdjointLossGradient(scene.model, parameters, observations);
      } else {
        result = CentralDifferenceLossGradient(scene.model, parameters, observations);
      }
    } catch (const InputError& e) {
      throw InputError(scene_path_ + ": " + e.what());
    } catch (const SimulationDiverged& e) {
      throw SimulationDiverged(scene_path_ + ": " + e.what(), e.time(), e.constraint());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // a loss or gradient that is not finite would print as null: a failure, never a result
    bool finite = std::isfinite(result.loss);
    for (int i = 0; i < parameters.size(); ++i) finite = finite && std::isfinite(result.gradient[i]);
    if (!finite) {
      std::cerr << "tether: " << scene_path_ << ": the loss or its gradient is not finite (an overflow in the "
                << "simulation or its derivatives)\n";
      return 1;
    }

    std::cout << GradientJson(parameters, scene.model, result, method_, seconds).dump(2) << std::endl;
    return 0;
  }

 private:
  CLI::App* app_;
  std::string scene_path_, data_path_, method_ = "jet";
  std::vector<std::string> pointers_;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeGradientCommand(CLI::App* parent) { return std::make_unique<GradientCommand>(parent); }

}  // namespace tether::cli
