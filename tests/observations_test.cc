// ReadObservations (observations.h): trajectory-CSV columns mapped to the q / v / energy entries they observe, for
// particles (2D and 3D) and planar rigid bodies; rows sorted by time; empty cells missing (NaN) and not counted;
// and every malformed file refused with an InputError naming the file and the line. MakeObservations (the same from
// rows in memory, for the Python module) gives what the file gives and names the row in its refusals.
#include "tether/autodiff/observations.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using testing::SceneFromJson;
using Kind = TrajectoryColumn::Kind;

// A particle (q 0..1) and a rigid body (q 2..4: x, y, angle), simulated for 0.5 s.
const char* kPlanarScene = R"({
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.6, -0.35]},
             {"name": "bar", "type": "rigid", "mass": 2.0, "inertia": 0.1, "position": [1.0, 0.5], "angle": 0.3}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"duration": 0.5}})";

// Files in a scratch folder (test_files.h), removed at the end.
class ObservationsTest : public ::testing::Test {
 protected:
  void SetUp() override { model_ = SceneFromJson(kPlanarScene); }

  std::string Write(const std::string& name, const std::string& text) const { return folder_.Write(name, text); }

  // Expects ReadObservations to refuse `text` with a message naming the file, `line` (when > 0) and `detail`.
  void ExpectRefused(const std::string& text, int line, const std::string& detail) {
    const std::string path = Write("bad.csv", text);
    try {
      ReadObservations(path, model_);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      if (line > 0) EXPECT_NE(message.find("line " + std::to_string(line)), std::string::npos) << message;
      EXPECT_NE(message.find(detail), std::string::npos) << message;
    }
  }

  testing::TempFolder folder_{"tether_obs"};
  Model<double> model_;
};

void ExpectColumn(const TrajectoryColumn& column, const std::string& name, Kind kind, int index) {
  EXPECT_EQ(column.name, name);
  EXPECT_EQ(column.kind, kind) << name;
  EXPECT_EQ(column.index, index) << name;
}

TEST_F(ObservationsTest, ColumnsMapToCoordinatesVelocitiesAndEnergy) {
  const std::string path = Write("obs.csv",
                                 "bar.angle,bob.x,t,bob.vy,energy,bar.omega,bar.y,bar.vx\n"
                                 "0.3,0.6,0.0,0.0,1.5,0.0,0.5,0.0\n");
  const Observations obs = ReadObservations(path, model_);
  EXPECT_EQ(obs.path, path);
  ASSERT_EQ(obs.columns.size(), 7u);  // t is not an observed column
  ExpectColumn(obs.columns[0], "bar.angle", Kind::kConfiguration, 4);
  ExpectColumn(obs.columns[1], "bob.x", Kind::kConfiguration, 0);
  ExpectColumn(obs.columns[2], "bob.vy", Kind::kVelocity, 1);
  EXPECT_EQ(obs.columns[3].kind, Kind::kEnergy);
  EXPECT_EQ(obs.columns[3].name, "energy");
  ExpectColumn(obs.columns[4], "bar.omega", Kind::kVelocity, 4);
  ExpectColumn(obs.columns[5], "bar.y", Kind::kConfiguration, 3);
  ExpectColumn(obs.columns[6], "bar.vx", Kind::kVelocity, 2);
  ASSERT_EQ(obs.times.size(), 1u);
  EXPECT_EQ(obs.values[0], (std::vector<double>{0.3, 0.6, 0.0, 1.5, 0.0, 0.5, 0.0}));
  EXPECT_EQ(obs.lines, std::vector<int>{2});
}

// A run evaluates the energy only for observations that have its column (RunOptions::energy): without it the
// samples carry NaN there, with it the energy, and the other columns are the same either way.
// names from scene files and imported models may hold a comma or a quote: the trajectory's header quotes them
// (RFC 4180) and the data reader takes them back, from a file saved by a spreadsheet too (a byte-order mark, CRLF)
TEST_F(ObservationsTest, QuotedNamesABomAndCrlfLinesAreRead) {
  const Model<double> model = SceneFromJson(R"({"dimension": 2,
    "bodies": [{"name": "bob, \"the\" bob", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
    "simulation": {"duration": 0.5}})");
  std::ostringstream trajectory;
  TrajectoryCsvWriter writer(model, &trajectory);
  EXPECT_EQ(trajectory.str().substr(0, trajectory.str().find('\n')),
            R"(t,"bob, ""the"" bob.x","bob, ""the"" bob.y","bob, ""the"" bob.vx","bob, ""the"" bob.vy",)"
            "constraint_error,energy");
  const Observations obs =
      ReadObservations(Write("saved.csv", "\xEF\xBB\xBFt,\"bob, \"\"the\"\" bob.x\"\r\n0.25,0.5\r\n"), model);
  ASSERT_EQ(obs.columns.size(), 1u);
  EXPECT_EQ(obs.columns[0].name, "bob, \"the\" bob.x");
  EXPECT_EQ(obs.values[0][0], 0.5);
  ExpectRefused("t,\"bob.x\n0.25,0.5\n", 1, "a quoted cell is not closed");
}

TEST_F(ObservationsTest, TheEnergyIsEvaluatedOnlyWhenObserved) {
  const Observations with = ReadObservations(Write("with.csv", "t,bob.x,energy\n0.25,0.5,1.0\n"), model_);
  const Observations without = ReadObservations(Write("without.csv", "t,bob.x\n0.25,0.5\n"), model_);
  EXPECT_TRUE(ObservesEnergy(with));
  EXPECT_FALSE(ObservesEnergy(without));
  for (const bool energy : {true, false}) {
    RunOptions options;
    options.energy = energy;
    int samples = 0;
    Simulate<double>(model_, options, [&](const Sample<double>& s) {
      ++samples;
      EXPECT_EQ(std::isfinite(s.energy), energy) << s.t;
      EXPECT_TRUE(std::isfinite(s.q[0]));
    });
    EXPECT_GT(samples, 1);
  }
}

TEST_F(ObservationsTest, ParticleZColumnsIn3D) {
  const Model<double> model = SceneFromJson(R"({"dimension": 3,
    "bodies": [{"name": "a", "type": "particle", "mass": 1.0, "position": [0.0, 0.0, 0.0]},
               {"name": "b", "type": "particle", "mass": 1.0, "position": [1.0, 2.0, 3.0]}]})");
  const std::string path = Write("obs3.csv", "t,b.z,b.vz,a.vy,b.x\n0.5,3.0,0.0,0.0,1.0\n");
  const Observations obs = ReadObservations(path, model);
  ASSERT_EQ(obs.columns.size(), 4u);
  ExpectColumn(obs.columns[0], "b.z", Kind::kConfiguration, 5);
  ExpectColumn(obs.columns[1], "b.vz", Kind::kVelocity, 5);
  ExpectColumn(obs.columns[2], "a.vy", Kind::kVelocity, 1);
  ExpectColumn(obs.columns[3], "b.x", Kind::kConfiguration, 3);
}

TEST_F(ObservationsTest, RowsAreSortedByTimeWithTheirLines) {
  const std::string path = Write("unsorted.csv",
                                 "t,bob.x,bob.y\n"
                                 "0.5,5.0,-5.0\n"
                                 "0.1234,1.0,-1.0\n"
                                 "\n"  // blank lines are skipped but still counted
                                 "0.3,3.0,-3.0\n"
                                 "0,0.5,-0.5\n");
  const Observations obs = ReadObservations(path, model_);
  EXPECT_EQ(obs.times, (std::vector<double>{0.0, 0.1234, 0.3, 0.5}));  // exact: as written in the file
  ASSERT_EQ(obs.values.size(), 4u);
  EXPECT_EQ(obs.values[0], (std::vector<double>{0.5, -0.5}));
  EXPECT_EQ(obs.values[1], (std::vector<double>{1.0, -1.0}));
  EXPECT_EQ(obs.values[2], (std::vector<double>{3.0, -3.0}));
  EXPECT_EQ(obs.values[3], (std::vector<double>{5.0, -5.0}));
  EXPECT_EQ(obs.lines, (std::vector<int>{6, 3, 5, 2}));
  EXPECT_EQ(obs.CellCount(), 8);
}

TEST_F(ObservationsTest, EmptyCellsAreMissing) {
  const std::string path = Write("gaps.csv",
                                 "t,bob.x,bob.vx,energy\n"
                                 "0.1,,0.25,\n"
                                 "0.2, 1.5 ,,-2\n"
                                 "0.3,,,7.5\n");
  const Observations obs = ReadObservations(path, model_);
  ASSERT_EQ(obs.values.size(), 3u);
  EXPECT_TRUE(std::isnan(obs.values[0][0]));
  EXPECT_EQ(obs.values[0][1], 0.25);
  EXPECT_TRUE(std::isnan(obs.values[0][2]));  // a trailing empty cell
  EXPECT_EQ(obs.values[1][0], 1.5);           // spaces around a number are allowed
  EXPECT_TRUE(std::isnan(obs.values[1][1]));
  EXPECT_EQ(obs.values[1][2], -2.0);
  EXPECT_TRUE(std::isnan(obs.values[2][0]));
  EXPECT_TRUE(std::isnan(obs.values[2][1]));
  EXPECT_EQ(obs.values[2][2], 7.5);
  EXPECT_EQ(obs.CellCount(), 4);
}

TEST_F(ObservationsTest, TimesAtBothEndsOfTheIntervalAreAccepted) {
  const Observations obs = ReadObservations(Write("ends.csv", "t,bob.x\n0,1\n0.5,2\n"), model_);
  EXPECT_EQ(obs.times, (std::vector<double>{0.0, 0.5}));
}

TEST_F(ObservationsTest, UnknownColumnIsRefused) {
  ExpectRefused("t,bob.x,bob.angle\n0.1,1,2\n", 1, "bob.angle");  // a particle has no angle
  ExpectRefused("t,ghost.x\n0.1,1\n", 1, "ghost.x");
  ExpectRefused("t,bob.z\n0.1,1\n", 1, "bob.z");  // a planar scene has no z
}

TEST_F(ObservationsTest, ConstraintErrorColumnIsRefused) {
  ExpectRefused("t,bob.x,constraint_error\n0.1,1,0\n", 1, "constraint_error");
}

TEST_F(ObservationsTest, DuplicateColumnIsRefused) {
  ExpectRefused("t,bob.x,bar.y,bob.x\n0.1,1,2,3\n", 1, "bob.x");
  ExpectRefused("t,bob.x,t\n0.1,1,0.2\n", 1, "'t'");
}

TEST_F(ObservationsTest, MissingTimeColumnIsRefused) {
  ExpectRefused("bob.x,bob.y\n1,2\n", 1, "'t'");
  ExpectRefused("t\n0.1\n", 1, "no observed column");
}

TEST_F(ObservationsTest, NonNumberCellIsRefused) {
  ExpectRefused("t,bob.x\n0.1,1\n0.2,abc\n", 3, "abc");
  ExpectRefused("t,bob.x\n0.1,1\n0.2,2\n0.3,1.5x\n", 4, "bob.x");
  ExpectRefused("t,bob.x\n0.1,nan\n", 2, "bob.x");
  ExpectRefused("t,bob.x\nzero,1\n", 2, "zero");
  ExpectRefused("t,bob.x\n0.1,1\n,2\n", 3, "'t'");  // a missing time
}

TEST_F(ObservationsTest, TimeOutsideTheIntervalIsRefused) {
  ExpectRefused("t,bob.x\n0.1,1\n-0.01,2\n", 3, "-0.01");
  ExpectRefused("t,bob.x\n0.1,1\n0.2,2\n0.51,3\n", 4, "0.51");
}

TEST_F(ObservationsTest, RepeatedTimeIsRefused) {
  // reported at the later line (in time order), naming the earlier one
  ExpectRefused("t,bob.x\n0.2,1\n0.1,2\n0.2,3\n", 4, "line 2");
}

TEST_F(ObservationsTest, WrongNumberOfCellsIsRefused) {
  ExpectRefused("t,bob.x,bob.y\n0.1,1,2\n0.2,1\n", 3, "got 2");
  ExpectRefused("t,bob.x,bob.y\n0.1,1,2,3\n", 2, "got 4");
}

TEST_F(ObservationsTest, EmptyFileIsRefused) {
  ExpectRefused("", 0, "empty");
  ExpectRefused("t,bob.x\n", 0, "no rows");
}

TEST_F(ObservationsTest, RowsInMemoryGiveWhatTheFileGives) {
  const std::string path = Write("gaps.csv",
                                 "t,bob.x,bob.vx,energy\n"
                                 "0.3,,,7.5\n"
                                 "0.1,,0.25,\n"
                                 "0.2,1.5,,-2\n");
  const Observations from_file = ReadObservations(path, model_);
  const Observations in_memory =
      MakeObservations("data", {"t", "bob.x", "bob.vx", "energy"},
                       {{0.3, NAN, NAN, 7.5}, {0.1, NAN, 0.25, NAN}, {0.2, 1.5, NAN, -2.0}}, model_);
  EXPECT_EQ(in_memory.path, "data");
  EXPECT_EQ(in_memory.times, from_file.times);
  ASSERT_EQ(in_memory.columns.size(), from_file.columns.size());
  for (size_t c = 0; c < in_memory.columns.size(); ++c) {
    ExpectColumn(in_memory.columns[c], from_file.columns[c].name, from_file.columns[c].kind,
                 from_file.columns[c].index);
  }
  ASSERT_EQ(in_memory.values.size(), 3u);
  for (size_t r = 0; r < 3; ++r) {
    for (size_t c = 0; c < 3; ++c) {
      const double a = in_memory.values[r][c], b = from_file.values[r][c];
      EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << r << ", " << c;
    }
  }
  EXPECT_EQ(in_memory.lines, (std::vector<int>{2, 3, 1}));  // the rows, from 1, where the file has lines
  EXPECT_EQ(in_memory.CellCount(), from_file.CellCount());
}

TEST_F(ObservationsTest, RowsInMemoryAreRefusedByRow) {
  auto expect_refused = [this](const std::vector<std::string>& names, const std::vector<std::vector<double>>& rows,
                               const std::string& detail) {
    try {
      MakeObservations("data", names, rows, model_);
      ADD_FAILURE() << "accepted: " << detail;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), "data: " + detail);
    }
  };
  expect_refused({"t", "bob.x"}, {{0.1, 1.0}, {0.2, INFINITY}}, "row 2: column 'bob.x': the value is infinite");
  expect_refused({"t", "bob.x"}, {{0.1, 1.0}, {NAN, 1.0}}, "row 2: the time 't' is missing");
  expect_refused({"t", "bob.x"}, {{0.1, 1.0}, {0.1, 2.0}}, "row 2: repeats the time of row 1");
  expect_refused({"t", "bob.x"}, {{0.1}}, "row 1: expected 2 values, got 1");
  expect_refused({"t", "bob.x"}, {{0.7, 1.0}},
                 "row 1: t = 0.69999999999999996 lies outside the simulated interval [0, 0.5]");
  expect_refused({"bob.x"}, {{1.0}}, "no 't' column");
  expect_refused({"t", "bob.x"}, {}, "the data has no rows");
  expect_refused({"t", "bob.x"}, {{0.1, NAN}, {0.2, NAN}},
                 "the data has no observed value: every cell besides 't' is empty");
}

// nothing to fit is refused, not fitted with a loss of zero (and no empty residual reaches an SVD)
TEST_F(ObservationsTest, AFileWithoutAnyValueIsRefused) {
  ExpectRefused("t,bob.x,bob.y\n0.1,,\n0.2, ,\n", 0, "has no observed value: every cell besides 't' is empty");
}

TEST_F(ObservationsTest, MissingFileIsRefused) {
  const std::string path = folder_.Path("does_not_exist.csv");
  try {
    ReadObservations(path, model_);
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tether
