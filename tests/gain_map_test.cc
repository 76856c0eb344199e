// The marks of a gain_map figure (studies/include/tether/studies/gain_map.h): one panel per combination of the
// columns other than the gains, its bound curve on h omega = B(zeta) with the error dynamics unstable just past
// it, and the presets and the panel's tuned gains as marks.
#include "tether/studies/gain_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_files.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/tuning/gain_tuning.h"
#include "tether/tuning/stability.h"

namespace tether {
namespace {

const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.01, "duration": 0.5}})";

TEST(GainMapMarks, BoundCurveAndMarksForEachPanel) {
  testing::TempFolder folder("tether_gain_map");
  folder.Write("pendulum.json", kPendulum);
  const std::string study = folder.Write("map.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/integrator": ["rk4", "symplectic_euler"], "/stabilization/alpha": [1, 10],
              "/stabilization/beta": [10, 100], "/simulation/step": [0.01]},
    "metrics": ["max_constraint_error"], "figures": [{"type": "gain_map", "color": "max_constraint_error"}]})");
  const StudySpec spec = ReadStudySpec(study);
  const nlohmann::json marks = GainMapMarks(spec);
  ASSERT_EQ(marks["panels"].size(), 2u);
  const Integrator integrators[] = {Integrator::kRk4, Integrator::kSymplecticEuler};
  const char* names[] = {"rk4", "symplectic_euler"};
  for (int p = 0; p < 2; ++p) {
    const nlohmann::json& panel = marks["panels"][p];
    EXPECT_EQ(panel["values"]["/simulation/integrator"], names[p]);
    EXPECT_EQ(panel["values"]["/simulation/step"], "0.01");
    EXPECT_FALSE(panel["values"].contains("/stabilization/alpha"));
    const double h = panel["step"];
    EXPECT_EQ(h, 0.01);
    ASSERT_GT(panel["bound"].size(), 100u);
    for (const nlohmann::json& point : panel["bound"]) {
      const double alpha = point[0], beta = point[1];
      const double omega = std::sqrt(beta), zeta = alpha / (2.0 * omega);
      EXPECT_NEAR(h * omega, StabilityBound(integrators[p], zeta), 1e-12 * h * omega) << names[p] << " zeta " << zeta;
    }
    // just past the curve the discrete error dynamics grow (checked where the crossing is clean, zeta ~ 1)
    const nlohmann::json& middle = panel["bound"][panel["bound"].size() / 2];
    const double omega = std::sqrt(middle[1].get<double>()), zeta = middle[0].get<double>() / (2.0 * omega);
    EXPECT_GT(AmplificationRadius(integrators[p], 1.01 * h * omega, zeta), 1.0);
    EXPECT_LE(AmplificationRadius(integrators[p], 0.99 * h * omega, zeta), 1.0);

    Model<double> model = ParseScene(ParseJsonText(kPendulum, "p.json"), "p.json").model;
    model.simulation.integrator = integrators[p];
    const TuneResult tuned = TuneGains(model, TuneSettings{});
    const std::vector<NamedGains> presets = GainPresets(integrators[p], h);
    ASSERT_EQ(panel["marks"].size(), presets.size());  // the presets but "none", then "tuned"
    for (size_t k = 1; k < presets.size(); ++k) {
      EXPECT_EQ(panel["marks"][k - 1]["name"], presets[k].name);
      EXPECT_EQ(panel["marks"][k - 1]["alpha"], presets[k].alpha);
      EXPECT_EQ(panel["marks"][k - 1]["beta"], presets[k].beta);
    }
    EXPECT_EQ(panel["marks"].back()["name"], "tuned");
    EXPECT_NEAR(panel["marks"].back()["alpha"].get<double>(), tuned.alpha, 1e-12 * tuned.alpha);
    EXPECT_NEAR(panel["marks"].back()["beta"].get<double>(), tuned.beta, 1e-12 * tuned.beta);
  }
}

}  // namespace
}  // namespace tether
