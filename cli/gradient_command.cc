#include "gradient_command.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include "scene_overrides.h"
#include "scene_run.h"
#include "tether/autodiff/gradient_method.h"
#include "tether/dynamics/model/errors.h"

namespace tether::cli {
namespace {

class GradientCommand final : public Command {
 public:
  explicit GradientCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("gradient", "loss against observations and its gradient with respect to parameters");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    app_->add_option("--data", data_path_, "observations: a trajectory CSV with t and any subset of columns")->required();
    app_->add_option("--param", pointers_, "a parameter, as a JSON Pointer into the scene (repeatable)")->required();
    app_->add_option("--tie", ties_, "PTR=EXPR: PTR follows EXPR of other scene numbers in braces (repeatable)");
    app_->add_option("--method", method_,
                     "auto (default: jet below " + std::to_string(kAdjointCrossover) +
                         " parameters, adjoint from there), adjoint (the discrete adjoint), jet (Jets through the KKT "
                         "solves) or fd (central differences)");
    overrides_.Register(app_);
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    const GradientMethod requested = ParseGradientMethod(method_, "--method");
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    ParameterSet parameters(scene, pointers_);
    parameters.Tie(scene, ties_);
    const Observations observations = ReadObservations(data_path_, scene.model);

    const auto start = std::chrono::steady_clock::now();
    const GradientMethod method = ResolveGradientMethod(requested, parameters.size());
    AdjointReport adjoint;
    const LossGradient result = NamingScene(
        scene_path_, [&] { return LossGradientBy(method, scene.model, parameters, observations, &adjoint); });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // a loss or gradient that is not finite would print as null: a failure, never a result
    bool finite = std::isfinite(result.loss);
    for (int i = 0; i < parameters.size(); ++i) finite = finite && std::isfinite(result.gradient[i]);
    if (!finite) {
      std::cerr << "tether: " << scene_path_ << ": the loss or its gradient is not finite (an overflow in the "
                << "simulation or its derivatives)\n";
      return 1;
    }

    std::cout << GradientJson(parameters, scene.model, result, method, seconds, adjoint).dump(2) << std::endl;
    return 0;
  }

 private:
  CLI::App* app_;
  std::string scene_path_, data_path_, method_ = "auto";
  std::vector<std::string> pointers_, ties_;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeGradientCommand(CLI::App* parent) { return std::make_unique<GradientCommand>(parent); }

}  // namespace tether::cli
