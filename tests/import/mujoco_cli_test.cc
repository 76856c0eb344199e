// The README's humanoid, through the command line: MuJoCo's humanoid imported hanging by its torso simulates,
// tunes, and gives back the forearm's mass from the shipped recording of its joint encoders
// (docs/examples/humanoid/make_recording.py: the truth is 1.31146 kg); its knees and elbows swing into their
// limits, imported active, and no limit is exceeded by more than 1e-8 rad at any output row; its view over 3 s is
// well under 2 MB (docs/view.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_files.h"

namespace tether::testing {
namespace {

constexpr double kTruth = 0.9614576197247512 + 0.35;  // MuJoCo's forearm and the weight strapped to it, kg

TEST(HumanoidCli, ImportsSimulatesTunesAndIdentifiesAsTheReadmeShows) {
  const TempFolder folder;
  const std::string scene = folder.Path("humanoid.json");
  const Outcome imported = RunTether(
      "import /usr/share/mujoco/model/humanoid/humanoid.xml --fix torso --no-contact "
      "--joint-velocity left_elbow=2 --joint-velocity right_knee=-1.5 -o " +
          scene,
      folder);
  ASSERT_EQ(imported.status, 0) << imported.err;
  const Outcome simulated = RunTether("simulate " + scene + " --duration 3 -o " + folder.Path("humanoid.csv"), folder);
  EXPECT_EQ(simulated.status, 0) << simulated.err;
  const Outcome tuned = RunTether("tune " + scene + " --max-evaluations 20", folder);
  EXPECT_EQ(tuned.status, 0) << tuned.err;
#ifdef TETHER_HAVE_VIEWER
  const std::string report = " --report " + folder.Path("report.html");  // as docs/reports.md says it is written
#else
  const std::string report;
#endif
  const Outcome identified = RunTether("identify " + scene + " --duration 3 --data " + std::string(TETHER_SOURCE_DIR) +
                                           "/docs/examples/humanoid/joint_angles.csv --param /bodies/12/mass" + report,
                                       folder);
  ASSERT_EQ(identified.status, 0) << identified.err;
#ifdef TETHER_HAVE_VIEWER
  const std::string html = ReadText(folder.Path("report.html"));
  EXPECT_LT(html.size(), 2000000u);
  for (const char* column :
       {"abdomen_x.angle", "right_knee.angle", "left_knee.angle", "right_elbow.angle", "left_elbow.angle"}) {
    EXPECT_NE(html.find("\"column\":\"" + std::string(column) + "\""), std::string::npos) << column;
  }
#endif
  const nlohmann::json result = nlohmann::json::parse(identified.out);
  const double mass = result["parameters"]["/bodies/12/mass"],
               deviation = result["standard_deviation"]["/bodies/12/mass"];
  EXPECT_FALSE(result["failed"].get<bool>());
  EXPECT_LT(std::abs(mass - kTruth), 3 * deviation) << mass << " +- " << deviation;
  EXPECT_LT(deviation, 1e-3);
}

TEST(HumanoidCli, KneesAndElbowsSwingIntoTheirLimitsAndStayWithin) {
  const TempFolder folder;
  const std::string scene = folder.Path("humanoid.json");
  ASSERT_EQ(RunTether("import /usr/share/mujoco/model/humanoid/humanoid.xml --fix torso --no-contact --joint-velocity "
                      "left_elbow=2 --joint-velocity right_knee=-1.5 -o " +
                          scene,
                      folder)
                .status,
            0);
  const nlohmann::json document = nlohmann::json::parse(ReadText(scene));
  std::map<std::string, std::pair<double, double>> ranges;
  for (const nlohmann::json& c : document["constraints"]) {
    if (c.contains("range")) ranges[c["name"]] = {c["range"][0], c["range"][1]};
  }
  ASSERT_EQ(ranges.size(), 5u);  // abdomen_x, both knees, both elbows
  const Outcome run = RunTether(
      "simulate " + scene + " --duration 3 -o " + folder.Path("run.csv") + " --events " + folder.Path("events.csv"),
      folder);
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> lines = Lines(ReadText(folder.Path("run.csv")));
  const std::vector<std::string> header = CsvCells(lines[0]);
  for (const auto& [joint, range] : ranges) {
    const size_t column = std::find(header.begin(), header.end(), joint + ".angle") - header.begin();
    ASSERT_LT(column, header.size()) << joint;
    double worst = -1.0;  // the largest excursion past a bound
    for (size_t row = 1; row < lines.size(); ++row) {
      const double angle = std::stod(CsvCells(lines[row])[column]);
      worst = std::max({worst, range.first - angle, angle - range.second});
    }
    EXPECT_LT(worst, 1e-8) << joint;
  }
  std::map<std::string, int> impacts;
  for (const std::string& line : Lines(ReadText(folder.Path("events.csv")))) {
    const std::vector<std::string> cells = CsvCells(line);
    if (cells.size() == 5 && cells[1] == "impact") ++impacts[cells[2]];
  }
  for (const char* joint : {"left_knee", "right_knee", "left_elbow", "right_elbow"})
    EXPECT_GT(impacts[joint], 0) << joint;
}

#ifdef TETHER_HAVE_VIEWER
TEST(HumanoidCli, ItsViewOverThreeSecondsIsWellUnderTwoMegabytes) {
  const TempFolder folder;
  const std::string scene = folder.Path("humanoid.json"), page = folder.Path("humanoid.html");
  ASSERT_EQ(RunTether("import /usr/share/mujoco/model/humanoid/humanoid.xml --fix torso --no-contact --joint-velocity "
                      "left_elbow=2 -o " +
                          scene,
                      folder)
                .status,
            0);
  const Outcome viewed = RunTether("view " + scene + " --duration 3 -o " + page, folder);
  ASSERT_EQ(viewed.status, 0) << viewed.err;
  const std::string html = ReadText(page);
  EXPECT_LT(html.size(), 1500000u);  // three.js is 850 kB of it
  EXPECT_NE(html.find("\"left_lower_arm\""), std::string::npos);
}

#endif

}  // namespace
}  // namespace tether::testing
