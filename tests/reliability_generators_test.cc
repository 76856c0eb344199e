// The reliability suite's generators (issue 34): instead of one reported case, every case of a class, drawn
// from the class itself, each with what must hold. The counts they print are docs/robustness.md's.
//   - numbers at the edges of their domains: every number of a scene that uses every kind of body, joint,
//     effect, limit and setting, replaced in turn by each edge value; the scene is read and, when accepted, run
//     for a few steps. Each case is accepted (and runs or stops with a divergence that says when), or refused
//     with an InputError naming the file (and a pointer: the changed one, or the constraint it makes impossible);
//   - counts at and past their bounds: every bounded count of the command line at its bound and one past it;
//     past it, exit 2 naming the flag;
//   - names with every separator: a body named with each character CSV and its readers treat specially; the
//     trajectory's header has as many fields as every row, and the data reader reads the name back.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/autodiff/observations.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/csv_line.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using nlohmann::json;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A 3D scene with a particle and three rigid bodies, a joint of most kinds (a limit and a restitution among
// them), every effect, a marker and every setting written out: every number in it is a case.
const char* kEverything = R"({"dimension": 3,
  "bodies": [{"name": "p", "type": "particle", "mass": 1.0, "position": [0.5, 0.0, -0.5], "velocity": [0.0, 0.1, 0.0]},
             {"name": "a", "type": "rigid", "mass": 2.0, "inertia": [0.02, 0.03, 0.04], "position": [0.0, 0.0, -1.0],
              "orientation": [1.0, 0.0, 0.0, 0.0], "velocity": [0.0, 0.0, 0.0], "angular_velocity": [0.0, 0.5, 0.0]},
             {"name": "b", "type": "rigid", "mass": 1.0, "inertia": [0.01, 0.01, 0.01], "position": [0.0, 0.0, -1.5]},
             {"name": "c", "type": "rigid", "mass": 0.5, "inertia": [0.01, 0.01, 0.01], "position": [0.3, 0.0, -1.5]}],
  "constraints": [{"type": "hinge", "name": "shoulder", "bodies": ["world", "a"], "points": [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
                   "axis": [0.0, 1.0, 0.0], "range": [-1.0, 1.0], "restitution": 0.5},
                  {"type": "pin", "bodies": ["a", "b"], "points": [[0.0, 0.0, -0.25], [0.0, 0.0, 0.25]]},
                  {"type": "prismatic", "name": "rail", "bodies": ["b", "c"], "points": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                   "axis": [1.0, 0.0, 0.0], "range": [0.0, 0.6]},
                  {"type": "distance", "bodies": ["a", "p"], "points": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], "length": 0.70710678118654757}],
  "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]},
              {"type": "damping", "coefficient": 0.1, "angular_coefficient": 0.01},
              {"type": "spring", "bodies": ["world", "p"], "points": [[1.0, 0.0, -0.5], [0.0, 0.0, 0.0]], "stiffness": 10.0,
               "rest_length": 0.4, "damping": 0.2},
              {"type": "force", "body": "c", "point": [0.0, 0.0, 0.0], "value": [0.5, 0.0, 0.0]},
              {"type": "torque", "body": "a", "schedule": {"times": [0.0, 0.01], "values": [[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]}},
              {"type": "joint_torque", "joint": "shoulder", "value": 0.3},
              {"type": "joint_spring", "joint": "rail", "stiffness": 5.0, "rest": 0.3, "damping": 0.1},
              {"type": "drag", "body": "c", "point": [0.0, 0.1, 0.0], "density": 1.2, "drag_coefficient": 0.5, "area": 0.01}],
  "markers": [{"name": "tip", "body": "b", "point": [0.0, 0.0, -0.1]}],
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 0.005, "tolerance": 1e-8},
  "stabilization": {"method": "baumgarte", "alpha": 20.0, "beta": 100.0}})";

TEST(ReliabilityGenerators, EveryNumberOfAScene_AtTheEdgesOfItsDomain_IsRunOrRefusedNamingIt) {
  const json everything = json::parse(kEverything);
  ASSERT_NO_THROW(Simulate<double>(ParseScene(everything, "everything.json").model, RunOptions{},
                                   [](const Sample<double>&) {}));  // the scene itself runs
  const std::vector<std::string> pointers = testing::NumberPointers(everything);
  const std::vector<double> edges = {0.0,   -0.0,  -1.0,   1e-300, -1e-300, 1e300, -1e300,
                                     1e-12, 2.5e9, -2.5e9, 0.5,    1e6,     -1e6};
  int cases = 0, refused = 0, ran = 0, diverged = 0;
  for (const std::string& pointer : pointers) {
    for (double edge : edges) {
      json scene = everything;
      scene[json::json_pointer(pointer)] = edge;
      ++cases;
      Model<double> model;
      try {
        model = ParseScene(scene, "everything.json").model;
      } catch (const InputError& e) {
        ++refused;
        EXPECT_TRUE(Contains(e.what(), "everything.json: ")) << pointer << " = " << edge << ": " << e.what();
        continue;
      }
      model.simulation.duration = std::min(model.simulation.duration, 0.005);  // a few steps whatever was set
      model.simulation.step = std::max(model.simulation.step, 1e-4);
      try {
        Simulate<double>(model, RunOptions{}, [](const Sample<double>& s) {
          if (!std::isfinite(s.t)) throw std::logic_error("a sample at a non-finite time");
        });
        ++ran;
      } catch (const SimulationDiverged& e) {
        ++diverged;
        EXPECT_TRUE(Contains(e.what(), "t = ") || Contains(e.what(), "at t")) << pointer << ": " << e.what();
      } catch (const InputError& e) {  // cannot be assembled: refused before the first step
        ++refused;
      }
    }
  }
  std::cout << "numbers at the edges: " << pointers.size() << " numbers x " << edges.size() << " values = " << cases
            << " cases: " << refused << " refused naming the file, " << ran << " ran, " << diverged
            << " diverged with a message\n";
  EXPECT_EQ(cases, refused + ran + diverged);
  EXPECT_GT(refused, 0);
  EXPECT_GT(ran, 0);
}

TEST(ReliabilityGenerators, EveryBoundedCount_AtItsBoundAndPastIt) {
  const testing::TempFolder folder("tether_generators");
  const std::string scene = std::string(TETHER_SOURCE_DIR) + "/scenes/pendulum.json";
  const std::string data = folder.Write("data.csv", "t,bob.x\n0.5,0.6\n1,0.5\n");
  struct Bound {
    std::string command, flag;
    long long bound;
  };
  // each command given what lets it stop at once past the bound (nothing is run at the bound either: the flag's
  // check comes first, so a value at the bound must not be the reason for the exit)
  const std::vector<Bound> bounds = {
      {"tune '" + scene + "' --max-evaluations 2 --samples", "--samples", 1000},
      {"tune '" + scene + "' --samples 1 --max-evaluations", "--max-evaluations", 1000000},
      {"identify '" + scene + "' --data '" + data + "' --param /bodies/0/mass --max-evaluations", "--max-evaluations",
       1000000},
      {"identify '" + scene + "' --data '" + data + "' --param /bodies/0/mass --segments", "--segments", 100000},
      {"fit '" + scene + "' --data '" + data + "' --param /bodies/0/velocity/0 --starts", "--starts", 10000},
      {"study /nonexistent/study.json --out '" + folder.Path("s") + "' --threads", "--threads", 1024},
      {"simulate '" + scene + "' --every", "--every", 2147483647LL}};
  int cases = 0;
  for (const Bound& b : bounds) {
    for (long long value : {b.bound + 1, b.bound * 10 + 7, -1LL, 0LL}) {
      if (value == 0 && b.flag == "--segments") continue;  // 0 is nothing past a bound there
      ++cases;
      const testing::Outcome run = testing::RunTether(b.command + " " + std::to_string(value), folder);
      EXPECT_EQ(run.status, 2) << b.command << " " << value << "\n" << run.err;
      EXPECT_TRUE(Contains(run.err, b.flag)) << b.command << " " << value << "\n" << run.err;
    }
    ++cases;
    const testing::Outcome at = testing::RunTether(b.command + " " + std::to_string(b.bound) + " --help", folder);
    EXPECT_EQ(at.status, 0) << b.command << " " << b.bound << "\n" << at.err;  // the value parses at its bound
  }
  std::cout << "counts: " << bounds.size() << " bounded counts, " << cases << " cases at and past their bounds\n";
}

TEST(ReliabilityGenerators, BodyNamesWithEverySeparator_MakeCsvWhoseNamesReadBack) {
  const std::vector<std::string> specials = {",", "\"",           "\n",        "\r", "\r\n", ";", "\t",
                                             " ", "\xEF\xBB\xBF", "''",        "\\", "#",    "=", "@",
                                             ":", "\xC3\xA9",     "a,\"b\"\nc"};
  int cases = 0;
  for (const std::string& special : specials) {
    ++cases;
    const std::string name = "bob" + special + "x";
    json scene = json::parse(R"({"dimension": 2,
      "bodies": [{"name": "", "type": "particle", "mass": 1.0, "position": [0.6, -0.35]}],
      "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
      "simulation": {"step": 0.01, "duration": 0.03}})");
    scene["bodies"][0]["name"] = name;
    const Model<double> model = ParseScene(scene, "names.json").model;
    std::ostringstream csv;
    TrajectoryCsvWriter writer(model, &csv);
    Simulate<double>(model, RunOptions{}, [&writer](const Sample<double>& s) { writer.Write(s); });
    // records: split at line ends outside quotes, as a CSV reader does
    std::vector<std::string> records(1);
    bool quoted = false;
    for (char c : csv.str()) {
      if (c == '"') quoted = !quoted;
      if (c == '\n' && !quoted) {
        records.emplace_back();
        continue;
      }
      records.back() += c;
    }
    records.pop_back();  // after the last line end
    const auto header = SplitCsvLine(records[0]);
    ASSERT_TRUE(header.has_value()) << name;
    std::string written = name;  // a line break in a cell is written as a space (csv_line.h)
    for (char& c : written) c = c == '\n' || c == '\r' ? ' ' : c;
    EXPECT_EQ((*header)[1], written + ".x");
    for (size_t r = 1; r < records.size(); ++r) {
      const auto row = SplitCsvLine(records[r]);
      ASSERT_TRUE(row.has_value()) << name;
      EXPECT_EQ(row->size(), header->size()) << name << ", row " << r;
    }
    // and the data reader takes the positions back by their names
    const testing::TempFolder folder("tether_names");
    std::string data = "t," + CsvCell((*header)[1]) + "," + CsvCell((*header)[2]) + "\n";
    for (size_t r = 1; r < records.size(); ++r) {
      const std::vector<std::string> row = *SplitCsvLine(records[r]);
      data += row[0] + "," + row[1] + "," + row[2] + "\n";
    }
    const Observations observed = ReadObservations(folder.Write("names.csv", data), model);
    ASSERT_EQ(observed.columns.size(), 2u) << name;
    EXPECT_EQ(observed.columns[0].name, name + ".x");
  }
  std::cout << "names: " << cases << " names with separators round trip through the trajectory CSV\n";
}

}  // namespace
}  // namespace tether
