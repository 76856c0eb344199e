// `tether tune` through the real binary: JSON with the gains, the objective, the stability report and the
// comparison with the presets, the same numbers as the library; a readable summary on stderr; --write-scene
// writes a scene with the tuned gains that `tether simulate` runs; exit status 2 naming the flag for bad flags.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/tuning/gain_tuning.h"

namespace tether {
namespace {

using testing::Outcome;
using testing::RunTether;
using testing::TempFolder;

// The shipped pendulum (scenes/pendulum.json) shortened to 1 s at h = 1e-2: a tuning run takes ~0.05 s.
const char* kPendulum = R"({
  "dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.8660254037844386, -0.5]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 1.0}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.01, "duration": 1.0}
})";

const std::vector<std::string> kComparison = {"tuned", "none", "rbdl", "mujoco", "default_rule"};

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class TuneCliTest : public ::testing::Test {
 protected:
  TuneCliTest() : folder_("tether_tune_cli") { scene_ = folder_.Write("pendulum.json", kPendulum); }

  Outcome Tune(const std::string& flags) { return RunTether("tune '" + scene_ + "' " + flags, folder_); }

  TempFolder folder_;
  std::string scene_;
};

TEST_F(TuneCliTest, PrintsGainsStabilityAndComparisonAsTheLibraryComputesThem) {
  const Outcome run = Tune("");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json out = nlohmann::json::parse(run.out);
  for (const char* key : {"alpha", "beta", "omega", "zeta", "objective", "window", "evaluations", "seconds"}) {
    ASSERT_TRUE(out.contains(key) && out[key].is_number()) << key << " in " << run.out;
  }
  const double omega = out["omega"].get<double>(), zeta = out["zeta"].get<double>();
  EXPECT_NEAR(out["alpha"].get<double>(), 2.0 * zeta * omega, 1e-12 * omega);
  EXPECT_NEAR(out["beta"].get<double>(), omega * omega, 1e-12 * omega * omega);
  ASSERT_TRUE(out["stability"].is_object()) << run.out;
  for (const char* key : {"h_omega", "bound", "margin", "omega_upper"}) {
    ASSERT_TRUE(out["stability"][key].is_number()) << key << " in " << run.out;
  }
  EXPECT_GT(out["stability"]["margin"].get<double>(), 0.0);
  EXPECT_NEAR(out["stability"]["h_omega"].get<double>(), 0.01 * omega, 1e-12 * omega);
  EXPECT_LE(omega, out["stability"]["omega_upper"].get<double>());

  ASSERT_TRUE(out["comparison"].is_array()) << run.out;
  ASSERT_EQ(out["comparison"].size(), kComparison.size());
  for (size_t i = 0; i < kComparison.size(); ++i) {
    const nlohmann::json& row = out["comparison"][i];
    EXPECT_EQ(row["name"], kComparison[i]);
    EXPECT_FALSE(row["diverged"].get<bool>()) << row.dump();
    // beta = 0 (none) is not a point of the objective: NaN, printed as null
    if (kComparison[i] == "none") {
      EXPECT_TRUE(row["objective"].is_null()) << row.dump();
    } else {
      ASSERT_TRUE(row["objective"].is_number()) << row.dump();
      EXPECT_LE(out["objective"].get<double>(), row["objective"].get<double>() * (1 + 1e-12)) << row.dump();
    }
  }

  // the library in process gives the same numbers (the run is deterministic; JSON prints doubles in
  // round-trip form: 1e-12 relative)
  const TuneResult expected = TuneGains(ReadSceneFile(scene_).model, TuneSettings{});
  EXPECT_NEAR(out["alpha"].get<double>(), expected.alpha, 1e-12 * expected.alpha);
  EXPECT_NEAR(out["beta"].get<double>(), expected.beta, 1e-12 * expected.beta);
  EXPECT_NEAR(out["objective"].get<double>(), expected.objective, 1e-12 * expected.objective);
  EXPECT_NEAR(out["stability"]["margin"].get<double>(), expected.margin, 1e-12);

  // the summary on stderr: the tuned gains, the stability line and a row for every preset
  EXPECT_TRUE(Contains(run.err, "tuned: alpha")) << run.err;
  EXPECT_TRUE(Contains(run.err, "stability: h omega")) << run.err;
  for (const std::string& name : kComparison) EXPECT_TRUE(Contains(run.err, "\n" + name + " ")) << name << run.err;
}

TEST_F(TuneCliTest, OtherObjectivesOptimizersAndSamplesRun) {
  const Outcome run = Tune("--objective drift --optimizer nlopt:LN_BOBYQA --samples 2 --max-evaluations 40");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json out = nlohmann::json::parse(run.out);
  EXPECT_EQ(out["objective_kind"], "drift");
  EXPECT_EQ(out["optimizer"], "nlopt:LN_BOBYQA");
  EXPECT_TRUE(std::isfinite(out["objective"].get<double>()));
  EXPECT_GT(out["stability"]["margin"].get<double>(), 0.0);
  EXPECT_LE(out["evaluations"].get<int>(), 42);  // the budget, the start and the value at the returned point
  // no reference with the drift objective: no position error (null)
  EXPECT_TRUE(out["comparison"][0]["rms_position_error"].is_null()) << out["comparison"][0].dump();
}

TEST_F(TuneCliTest, WriteSceneHasTheTunedGainsAndSimulates) {
  const std::string written = folder_.Path("tuned.json");
  const Outcome run = Tune("--write-scene '" + written + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json out = nlohmann::json::parse(run.out);

  const nlohmann::json scene = nlohmann::json::parse(testing::ReadText(written));
  ASSERT_TRUE(scene["stabilization"].is_object()) << scene.dump();
  EXPECT_EQ(scene["stabilization"]["method"], "baumgarte");
  EXPECT_EQ(scene["stabilization"]["alpha"].get<double>(), out["alpha"].get<double>());  // the same printed double
  EXPECT_EQ(scene["stabilization"]["beta"].get<double>(), out["beta"].get<double>());
  // everything else is the scene as given
  nlohmann::json rest = scene;
  rest.erase("stabilization");
  EXPECT_EQ(rest, nlohmann::json::parse(kPendulum));

  // the scene reader takes it with these gains, not the default rule, and `tether simulate` runs it
  const Model<double> model = ReadSceneFile(written).model;
  EXPECT_FALSE(model.stabilization.gains_from_rule);
  EXPECT_EQ(model.stabilization.method, Stabilization::kBaumgarte);
  EXPECT_EQ(model.stabilization.alpha, out["alpha"].get<double>());
  const Outcome simulate = RunTether("simulate '" + written + "'", folder_);
  ASSERT_EQ(simulate.status, 0) << simulate.err;
  EXPECT_EQ(std::count(simulate.out.begin(), simulate.out.end(), '\n'), 102) << "a header and 101 rows";
}

TEST_F(TuneCliTest, BadFlagsExitTwoNamingTheFlag) {
  struct Case {
    std::string flags, flag, value;
  };
  const Case cases[] = {{"--optimizer foo", "--optimizer", "foo"},
                        {"--optimizer nlopt:XX_NOPE", "--optimizer", "XX_NOPE"},
                        {"--objective xyz", "--objective", "xyz"},
                        {"--samples 0", "--samples", "0"},
                        // the gains and the method are what tune chooses: flags that would set them are refused
                        {"--alpha 5", "--alpha", "--alpha"},
                        {"--beta 5", "--beta", "--beta"},
                        {"--stabilization projection", "--stabilization", "--stabilization"}};
  const std::string written = folder_.Path("never.json");
  for (const Case& c : cases) {
    const Outcome run = Tune(c.flags + " -o '" + written + "'");
    EXPECT_EQ(run.status, 2) << c.flags << ": " << run.err;
    EXPECT_TRUE(Contains(run.err, c.flag)) << c.flags << ": " << run.err;
    EXPECT_TRUE(Contains(run.err, c.value)) << c.flags << ": " << run.err;
    EXPECT_EQ(run.out, "") << c.flags;
    const std::vector<std::string> entries = folder_.Entries();
    EXPECT_EQ(std::count(entries.begin(), entries.end(), "never.json"), 0) << c.flags << ": a scene was written";
  }
}

}  // namespace
}  // namespace tether
