// The README's humanoid, through the command line: MuJoCo's humanoid imported hanging by its torso simulates,
// tunes, and gives back the forearm's mass from the shipped recording of its joint encoders
// (docs/examples/humanoid/make_recording.py: the truth is 1.31146 kg).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "test_files.h"

namespace tether::testing {
namespace {

constexpr double kTruth = 0.9614576197247512 + 0.35;  // MuJoCo's forearm and the weight strapped to it, kg

TEST(HumanoidCli, ImportsSimulatesTunesAndIdentifiesAsTheReadmeShows) {
  const TempFolder folder;
  const std::string scene = folder.Path("humanoid.json");
  const Outcome imported = RunTether("import /usr/share/mujoco/model/humanoid/humanoid.xml --fix torso "
                                     "--joint-velocity left_elbow=2 --joint-velocity right_knee=-1.5 -o " + scene,
                                     folder);
  ASSERT_EQ(imported.status, 0) << imported.err;
  const Outcome simulated = RunTether("simulate " + scene + " --duration 3 -o " + folder.Path("humanoid.csv"), folder);
  EXPECT_EQ(simulated.status, 0) << simulated.err;
  const Outcome tuned = RunTether("tune " + scene + " --max-evaluations 20", folder);
  EXPECT_EQ(tuned.status, 0) << tuned.err;
  const Outcome identified =
      RunTether("identify " + scene + " --duration 3 --data " + std::string(TETHER_SOURCE_DIR) +
                    "/docs/examples/humanoid/joint_angles.csv --param /bodies/14/mass",
                folder);
  ASSERT_EQ(identified.status, 0) << identified.err;
  const nlohmann::json result = nlohmann::json::parse(identified.out);
  const double mass = result["parameters"]["/bodies/14/mass"], deviation = result["standard_deviation"]["/bodies/14/mass"];
  EXPECT_FALSE(result["failed"].get<bool>());
  EXPECT_LT(std::abs(mass - kTruth), 3 * deviation) << mass << " +- " << deviation;
  EXPECT_LT(deviation, 1e-3);
}

}  // namespace
}  // namespace tether::testing
