#include "check_command.h"

#include <cstdio>
#include <iostream>
#include <string>

#include "scene_overrides.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_check.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether::cli {
namespace {

class CheckCommand final : public Command {
 public:
  explicit CheckCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("check", "report a scene's degrees of freedom, rank, redundancy and conditioning");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    app_->add_flag("--json", json_, "print JSON instead of text");
    overrides_.Register(app_);
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    const SceneCheck c = CheckScene(scene.model);
    if (json_) {
      std::cout << SceneCheckJson(c).dump(2) << std::endl;
      return c.assembly_error.empty() ? 0 : 1;
    }
    std::printf("%s: %d coordinates, %d constraint rows of rank %d: %d degrees of freedom\n", scene_path_.c_str(),
                c.coordinates, c.constraint_rows, c.rank, c.degrees_of_freedom);
    if (c.redundant_constraints.empty()) {
      std::printf("redundant constraints: none\n");
    } else {
      std::printf("redundant: %d rows; constraints with a row that adds nothing:", c.constraint_rows - c.rank);
      for (int k : c.redundant_constraints) std::printf(" /constraints/%d", k);
      std::printf("\n");
    }
    if (c.worst_constraint >= 0) {
      std::printf("initial violation: %.3g m (%s)\n", c.initial_violation,
                  DescribeConstraint(scene.model, c.worst_constraint).c_str());
    }
    std::printf("conditioning of J M^-1/2: %.3g%s (the Schur complement's is its square); KKT path: %s\n",
                c.condition_number, c.condition_estimated ? " (estimated by power and inverse iteration)" : "", c.solver.c_str());
    for (const LimitCheck& l : c.limits) {
      auto side = [](bool has, double bound) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", bound);
        return has ? std::string(text) : std::string("open");
      };
      std::printf("limit: /constraints/%d%s%s: %s %.9g in [%s, %s], %s\n", l.constraint, l.name.empty() ? "" : " ",
                  l.name.c_str(), l.coordinate.c_str(), l.start, side(l.has_low, l.low).c_str(),
                  side(l.has_high, l.high).c_str(),
                  l.low_active    ? "active at the start on its low bound"
                  : l.high_active ? "active at the start on its high bound"
                                  : "inactive at the start");
    }
    for (const ContactCheck& contact : c.contacts) {
      std::printf("contact: %s (/shapes/%d, /shapes/%d): gap %.9g m at the start, %s\n", contact.pair.c_str(),
                  contact.shape_a, contact.shape_b, contact.gap, contact.touching ? "touching" : "apart");
    }
    if (c.contacts.empty() && !scene.model.shapes.empty()) std::printf("contact: no pair of shapes may touch\n");
    if (!c.assembly_error.empty()) {
      std::printf("cannot be assembled: %s\n", c.assembly_error.c_str());
      return 1;  // simulate refuses this scene
    }
    return 0;
  }

 private:
  CLI::App* app_;
  std::string scene_path_;
  bool json_ = false;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeCheckCommand(CLI::App* parent) { return std::make_unique<CheckCommand>(parent); }

}  // namespace tether::cli
