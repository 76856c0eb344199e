// `mpirun -n 2 tether study ...` (built with TETHER_MPI): the ranks share the rows and rank 0 writes the same
// results.csv as a single-process run, the wall time aside; a bad study is reported once, with status 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "csv_columns.h"
#include "test_files.h"

namespace tether {
namespace {

using testing::Outcome;
using testing::TempFolder;

// Open MPI refuses root without these flags, and two ranks on a one-core machine need --oversubscribe.
const std::string kMpirun = std::string("'") + TETHER_MPIEXEC + "' --allow-run-as-root --oversubscribe -n 2";

const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.01, "duration": 0.5}})";

TEST(StudyOverMpirun, TwoRanksWriteTheSingleProcessResults) {
  TempFolder folder("tether_mpirun"), alone("tether_mpirun_alone"), ranks("tether_mpirun_ranks");
  folder.Write("pendulum.json", kPendulum);
  const std::string study = folder.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/integrator": ["rk4", "symplectic_euler", "euler"], "/simulation/step": [0.01, 0.005, 0.002]},
    "metrics": ["rms_position_error", "max_constraint_error", "energy_drift", "seconds"]})");
  const Outcome single = testing::RunTether("study '" + study + "' --out '" + alone.path() + "' --threads 1", folder);
  ASSERT_EQ(single.status, 0) << single.err;
  const Outcome spread =
      testing::RunTether("study '" + study + "' --out '" + ranks.path() + "' --threads 1", folder, kMpirun);
  ASSERT_EQ(spread.status, 0) << spread.err;
  const std::string expected = testing::WithoutColumn(testing::ReadText(alone.Path("results.csv")), "seconds");
  EXPECT_EQ(testing::Lines(expected).size(), 10u);  // header + 9 rows
  EXPECT_EQ(testing::WithoutColumn(testing::ReadText(ranks.Path("results.csv")), "seconds"), expected);
  EXPECT_TRUE(std::filesystem::exists(ranks.Path("summary.md")));
  EXPECT_TRUE(std::filesystem::exists(ranks.Path("rms_position_error.png")));
  EXPECT_FALSE(std::filesystem::exists(ranks.Path("results.partial.csv")));
}

TEST(StudyOverMpirun, BadStudyIsReportedOnceWithStatusTwo) {
  TempFolder folder("tether_mpirun_bad"), out("tether_mpirun_bad_out");
  folder.Write("pendulum.json", kPendulum);
  const std::string study = folder.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/step": [0.01, -1.0]}, "metrics": ["seconds"]})");
  const Outcome run = testing::RunTether("study '" + study + "' --out '" + out.path() + "'", folder, kMpirun);
  EXPECT_EQ(run.status, 2) << run.err;
  const std::string message = "study.json (row 1): /simulation/step";
  const size_t first = run.err.find(message);
  ASSERT_NE(first, std::string::npos) << run.err;
  EXPECT_EQ(run.err.find(message, first + 1), std::string::npos) << "reported twice: " << run.err;
  EXPECT_TRUE(out.Entries().empty());
}

}  // namespace
}  // namespace tether
