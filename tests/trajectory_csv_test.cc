// The trajectory CSV of docs/contract.md: its columns for particles (2D, 3D) and planar rigid bodies, numbers that
// round-trip a double exactly, and an output file that appears only when committed.
#include "tether/dynamics/io/trajectory_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using ::tether::testing::CsvCells;
using ::tether::testing::Lines;

using testing::SceneFromJson;

using testing::TempFolder;

bool Exists(const std::string& path) { return std::ifstream(path).good(); }

// The names of the trajectory columns of a model, in order.
std::vector<std::string> ColumnNames(const Model<double>& model) {
  std::vector<std::string> names;
  for (const TrajectoryColumn& column : TrajectoryColumns(model)) names.push_back(column.name);
  return names;
}

// Hands the first sample of a run of `model` started at `start_time` to `use`, then stops the run. Free bodies
// are not moved by the assembly, so that sample holds the model's initial state exactly.
struct FirstSampleTaken {};
void WithFirstSample(const Model<double>& model, double start_time,
                     const std::function<void(const Sample<double>&)>& use) {
  RunOptions run;
  run.start_time = start_time;
  try {
    Simulate<double>(model, run, [&use](const Sample<double>& s) {
      use(s);
      throw FirstSampleTaken{};
    });
    ADD_FAILURE() << "the run gave no sample";
  } catch (const FirstSampleTaken&) {
  }
}

TEST(TrajectoryCsv, ParticleColumnsIn2d) {
  const Model<double> model =
      SceneFromJson(R"({"bodies": [{"name": "bob", "type": "particle", "mass": 1, "position": [0, 0]}]})");
  EXPECT_EQ(ColumnNames(model),
            (std::vector<std::string>{"t", "bob.x", "bob.y", "bob.vx", "bob.vy", "constraint_error", "energy"}));
}

TEST(TrajectoryCsv, ParticleColumnsIn3d) {
  const Model<double> model = SceneFromJson(R"({"dimension": 3, "bodies": [
      {"name": "p", "type": "particle", "mass": 1, "position": [0, 0, 0]},
      {"name": "q", "type": "particle", "mass": 1, "position": [1, 0, 0]}]})");
  EXPECT_EQ(ColumnNames(model),
            (std::vector<std::string>{"t", "p.x", "p.y", "p.z", "p.vx", "p.vy", "p.vz", "q.x", "q.y", "q.z", "q.vx",
                                      "q.vy", "q.vz", "constraint_error", "energy"}));
}

TEST(TrajectoryCsv, RigidBodyColumnsInSceneOrder) {
  const Model<double> model = SceneFromJson(R"({"bodies": [
      {"name": "crank", "type": "rigid", "mass": 1, "inertia": 0.1, "position": [0, 0]},
      {"name": "bob", "type": "particle", "mass": 1, "position": [1, 0]}]})");
  EXPECT_EQ(ColumnNames(model),
            (std::vector<std::string>{"t", "crank.x", "crank.y", "crank.angle", "crank.vx", "crank.vy", "crank.omega",
                                      "bob.x", "bob.y", "bob.vx", "bob.vy", "constraint_error", "energy"}));
}

TEST(TrajectoryCsv, WriterHeaderAndRowMatchTheColumns) {
  // the state q = (1, 2, 3, 4, 5), v = (6, 7, 8, 9, 10) at t = 0.5, taken by a run from there (samples come only
  // from Simulate); the inertia 0.125 keeps the energy exact: 1/2 (36 + 49) + 1/2 0.125 64 + 1/2 (81 + 100) = 137
  const Model<double> model = SceneFromJson(R"({"bodies": [
      {"name": "crank", "type": "rigid", "mass": 1, "inertia": 0.125, "position": [1, 2], "angle": 3,
       "velocity": [6, 7], "angular_velocity": 8},
      {"name": "bob", "type": "particle", "mass": 1, "position": [4, 5], "velocity": [9, 10]}]})");
  std::ostringstream out;
  TrajectoryCsvWriter writer(model, &out);
  WithFirstSample(model, 0.5, [&writer](const Sample<double>& s) {
    ASSERT_EQ(s.q, (VecX<double>(5) << 1, 2, 3, 4, 5).finished());
    ASSERT_EQ(s.v, (VecX<double>(5) << 6, 7, 8, 9, 10).finished());
    writer.Write(s);
  });
  const std::vector<std::string> lines = Lines(out.str());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(CsvCells(lines[0]), ColumnNames(model));
  // per body: coordinates, then velocities
  EXPECT_EQ(CsvCells(lines[1]), (std::vector<std::string>{"0.5", "1", "2", "3", "6", "7", "8", "4", "5", "9", "10",
                                                       "0", "137"}));
}

TEST(TrajectoryCsv, NumbersRoundTripExactly) {
  const Model<double> model =
      SceneFromJson(R"({"bodies": [{"name": "p", "type": "particle", "mass": 1, "position": [0, 0]}]})");
  // values whose shortest faithful decimal forms need all 17 significant digits, and extremes
  const std::vector<double> values = {0.1,
                                      1.0 / 3.0,
                                      M_PI,
                                      std::nextafter(1.0, 2.0),
                                      -2.5e17 + 2,
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::max(),
                                      -std::numeric_limits<double>::min(),
                                      123456789.01234567,
                                      std::exp(-40.0)};
  // two rows of seven fields (t, x, y, vx, vy, constraint_error, energy): t, x, y, vx and vy cycle through the
  // values (each value once), set as the run's start time and the particle's initial state (samples come only
  // from Simulate); constraint_error and energy are the run's own
  const auto value = [&values](size_t row, size_t field) { return values[(row * 5 + field) % values.size()]; };
  std::ostringstream out;
  TrajectoryCsvWriter writer(model, &out);
  std::vector<std::vector<double>> written;
  for (size_t row = 0; row < 2; ++row) {
    Model<double> at = model;
    at.bodies[0].position << value(row, 1), value(row, 2), 0.0;
    at.bodies[0].velocity << value(row, 3), value(row, 4), 0.0;
    WithFirstSample(at, value(row, 0), [&](const Sample<double>& s) {
      writer.Write(s);
      written.push_back({s.t, s.q[0], s.q[1], s.v[0], s.v[1], s.constraint_error, Value(s.energy)});
    });
  }
  const std::vector<std::string> lines = Lines(out.str());
  ASSERT_EQ(lines.size(), 3u);
  ASSERT_EQ(written.size(), 2u);
  for (size_t row = 0; row < 2; ++row) {
    const std::vector<std::string> fields = CsvCells(lines[row + 1]);
    ASSERT_EQ(fields.size(), 7u);
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i < 5) EXPECT_EQ(written[row][i], value(row, i)) << "the sample holds the state as given";
      EXPECT_EQ(std::strtod(fields[i].c_str(), nullptr), written[row][i]) << fields[i];
    }
  }
}

TEST(TrajectoryCsv, SimulatedRowsRoundTrip) {
  // a real run through the writer reads back to the very same doubles
  const Model<double> model = testing::Pendulum60("rk4", 1e-3, 0.05);
  std::ostringstream out;
  TrajectoryCsvWriter writer(model, &out);
  std::vector<std::vector<double>> rows;
  Simulate<double>(model, RunOptions{5}, [&](const Sample<double>& s) {
    writer.Write(s);
    rows.push_back({s.t, s.q[0], s.q[1], s.v[0], s.v[1], s.constraint_error, s.energy});
  });
  const std::vector<std::string> lines = Lines(out.str());
  ASSERT_EQ(lines.size(), rows.size() + 1);
  ASSERT_EQ(rows.size(), 11u);
  for (size_t r = 0; r < rows.size(); ++r) {
    const std::vector<std::string> fields = CsvCells(lines[r + 1]);
    ASSERT_EQ(fields.size(), rows[r].size());
    for (size_t i = 0; i < fields.size(); ++i) EXPECT_EQ(std::strtod(fields[i].c_str(), nullptr), rows[r][i]);
  }
}

TEST(TrajectoryCsv, AngleIsContinuous) {
  // a free wheel spinning at 10 rad/s for 1 s: the angle column reaches 10 rad, not 10 - 2 pi or 10 - 4 pi
  const Model<double> model = SceneFromJson(R"({"bodies": [
      {"name": "w", "type": "rigid", "mass": 1, "inertia": 0.1, "position": [0, 0], "angular_velocity": 10.0}]})");
  std::ostringstream out;
  TrajectoryCsvWriter writer(model, &out);
  Simulate<double>(model, RunOptions{100}, [&writer](const Sample<double>& s) { writer.Write(s); });
  const std::vector<std::string> lines = Lines(out.str());
  ASSERT_EQ(lines.size(), 12u);
  double previous = -1.0;
  for (size_t row = 1; row < lines.size(); ++row) {
    const std::vector<std::string> fields = CsvCells(lines[row]);
    ASSERT_EQ(fields.size(), 9u);
    const double t = std::strtod(fields[0].c_str(), nullptr), angle = std::strtod(fields[3].c_str(), nullptr);
    EXPECT_NEAR(angle, 10.0 * t, 1e-12);
    EXPECT_GT(angle, previous);
    previous = angle;
  }
}

TEST(AtomicOutputFile, CommittedFileAppearsWithItsContents) {
  const TempFolder folder("tether_csv");
  const std::string path = folder.path() + "/out.csv";
  {
    AtomicOutputFile file(path);
    file.stream() << "t,x\n0,1\n";
    EXPECT_FALSE(Exists(path)) << "the file appeared before Commit()";
    file.Commit();
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "t,x\n0,1\n");
  EXPECT_EQ(folder.Entries(), std::vector<std::string>{"out.csv"});  // no temporary left beside it
}

TEST(AtomicOutputFile, UncommittedFileLeavesNothing) {
  const TempFolder folder("tether_csv");
  const std::string path = folder.path() + "/out.csv";
  {
    AtomicOutputFile file(path);
    file.stream() << "t,x\n0,1\n";
    file.stream().flush();
  }
  EXPECT_FALSE(Exists(path));
  EXPECT_TRUE(folder.Entries().empty());
}

TEST(AtomicOutputFile, UncommittedFileKeepsAnOlderFile) {
  // a failed run does not clobber the result of an earlier one
  const TempFolder folder("tether_csv");
  const std::string path = folder.path() + "/out.csv";
  std::ofstream(path) << "old\n";
  {
    AtomicOutputFile file(path);
    file.stream() << "new\n";
  }
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "old");
  EXPECT_EQ(folder.Entries(), std::vector<std::string>{"out.csv"});
}

TEST(AtomicOutputFile, UnwritableFolderIsAnInputError) {
  const TempFolder folder("tether_csv");
  try {
    AtomicOutputFile file(folder.path() + "/no/such/folder/out.csv");
    FAIL() << "opened a file in a folder that does not exist";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out.csv"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tether
