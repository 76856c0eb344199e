// `tether study STUDY.json --out DIR [--threads N]` through the real binary: results.csv, summary.md and a PNG
// and an SVG figure per metric, index.html and a view of each finished run, a progress bar on stderr and exit
// status 0; the same results (the wall time
// aside) on one thread and on two; a diverged row does not fail the study; exit status 2 with the file and the
// JSON Pointer or flag named for bad input, and then no results.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "csv_columns.h"
#include "test_files.h"

namespace tether {
namespace {

using ::tether::testing::Lines;
using ::tether::testing::CsvCells;

using testing::Outcome;
using testing::ReadText;
using testing::TempFolder;
using testing::WithoutColumn;

// The acceptance checks' pendulum (1 kg bob, 0.7 m rod, released at rest from 60 degrees), rk4 at h = 0.01
// with explicit Baumgarte gains (stiff enough for euler at h = 0.01 to stay within 1% of the rod), for 0.5 s.
const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.01, "duration": 0.5},
  "stabilization": {"method": "baumgarte", "alpha": 20.0, "beta": 400.0}})";

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class StudyCliTest : public ::testing::Test {
 protected:
  // Writes pendulum.json and study.json beside it (`sweep`, `metrics` as JSON text); returns the study's path.
  std::string WriteStudy(const std::string& sweep, const std::string& metrics) const {
    folder_.Write("pendulum.json", kPendulum);
    return folder_.Write("study.json",
                         R"({"scene": "pendulum.json", "sweep": )" + sweep + R"(, "metrics": )" + metrics + "}");
  }
  Outcome Study(const std::string& study, const TempFolder& out, const std::string& flags = "") const {
    return testing::RunTether("study '" + study + "' --out '" + out.path() + "'" + flags, folder_);
  }
  // A figure file: present and more than 1000 bytes (an empty or broken plot is smaller).
  static void ExpectFigure(const std::string& path) {
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    EXPECT_GT(std::filesystem::file_size(path), 1000u) << path;
  }

  TempFolder folder_{"tether_study_cli"};
  TempFolder out_{"tether_study_cli_out"};
};

TEST_F(StudyCliTest, WritesResultsSummaryAndFiguresWithAProgressBar) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, 0.005], "/simulation/integrator": ["rk4", "euler"]})",
                                       R"(["rms_position_error", "max_constraint_error"])");
  const Outcome run = Study(study, out_, " --threads 2");
  ASSERT_EQ(run.status, 0) << run.err;

  const std::vector<std::string> lines = Lines(ReadText(out_.Path("results.csv")));
  ASSERT_EQ(lines.size(), 5u);  // header + 2 x 2 combinations
  EXPECT_EQ(lines[0], "/simulation/step,/simulation/integrator,rms_position_error,max_constraint_error,status");
  const std::vector<std::string> expected_keys = {"0.01,rk4,", "0.01,euler,", "0.005,rk4,", "0.005,euler,"};
  for (size_t i = 0; i < expected_keys.size(); ++i) {
    EXPECT_EQ(lines[i + 1].rfind(expected_keys[i], 0), 0u) << lines[i + 1];
    EXPECT_EQ(CsvCells(lines[i + 1]).back(), "ok") << lines[i + 1];
  }
  EXPECT_FALSE(std::filesystem::exists(out_.Path("results.partial.csv")));

  const std::string summary = ReadText(out_.Path("summary.md"));
  EXPECT_TRUE(Contains(summary, "/simulation/step")) << summary;
  EXPECT_TRUE(Contains(summary, "rms_position_error")) << summary;
  EXPECT_GT(Lines(summary).size(), 6u) << summary;  // a title, a table of 4 rows, the best values

  for (const std::string metric : {"rms_position_error", "max_constraint_error"}) {
    ExpectFigure(out_.Path(metric + ".png"));
    ExpectFigure(out_.Path(metric + ".svg"));
    EXPECT_EQ(ReadText(out_.Path(metric + ".png")).substr(1, 3), "PNG") << metric;
    EXPECT_TRUE(Contains(ReadText(out_.Path(metric + ".svg")), "<svg")) << metric;
  }

  // stderr is a file here, not a terminal: progress comes as plain lines, without carriage returns, up to 4 of 4
  EXPECT_FALSE(Contains(run.err, "\r")) << run.err;
  EXPECT_TRUE(Contains(run.err, "tether: 4/4 runs, about 0 s left\n")) << run.err;
}

TEST_F(StudyCliTest, DrawsParetoAndGainMapFiguresAndWritesTheMarks) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("figures.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/integrator": ["rk4", "symplectic_euler"], "/stabilization/alpha": [1, 10, 100],
              "/stabilization/beta": [10, 1000, 1.0e7]},
    "metrics": ["max_constraint_error", "seconds_per_simulated_second"],
    "figures": [{"type": "pareto", "x": "seconds_per_simulated_second", "y": "max_constraint_error"},
                {"type": "gain_map", "color": "max_constraint_error"}]})");
  const Outcome run = Study(study, out_);
  ASSERT_EQ(run.status, 0) << run.err;
  for (const std::string name : {"pareto_max_constraint_error_vs_seconds_per_simulated_second",
                                 "gain_map_max_constraint_error"}) {
    ExpectFigure(out_.Path(name + ".png"));
    ExpectFigure(out_.Path(name + ".svg"));
  }
  // no lines figure was asked for
  EXPECT_FALSE(std::filesystem::exists(out_.Path("max_constraint_error.png")));
  // the Pareto front: at least one run, no run on it beaten in both metrics by another run on it
  const std::vector<std::string> front =
      Lines(ReadText(out_.Path("pareto_max_constraint_error_vs_seconds_per_simulated_second.csv")));
  ASSERT_GE(front.size(), 2u);
  for (size_t i = 2; i < front.size(); ++i) {  // sorted by time, so the error must fall along the front
    EXPECT_LT(std::stod(CsvCells(front[i])[3]), std::stod(CsvCells(front[i - 1])[3])) << front[i];
  }
  const std::string marks = ReadText(out_.Path("gain_map_marks.json"));
  EXPECT_TRUE(Contains(marks, "\"tuned\"")) << marks;
  EXPECT_TRUE(Contains(marks, "\"bound\"")) << marks;
}

TEST_F(StudyCliTest, ResultsDoNotDependOnTheThreadCount) {
  const std::string study =
      WriteStudy(R"({"/stabilization/beta": [10.0, 100.0, 1000.0], "/simulation/integrator": ["rk4", "symplectic_euler"]})",
                 R"(["max_constraint_error", "seconds", "rms_position_error", "energy_drift"])");
  TempFolder out2("tether_study_cli_out2");
  const Outcome one = Study(study, out_, " --threads 1"), two = Study(study, out2, " --threads 2");
  ASSERT_EQ(one.status, 0) << one.err;
  ASSERT_EQ(two.status, 0) << two.err;
  const std::string a = ReadText(out_.Path("results.csv")), b = ReadText(out2.Path("results.csv"));
  ASSERT_EQ(Lines(a).size(), 7u);
  // the wall time differs from run to run; everything else is identical, character for character
  EXPECT_EQ(WithoutColumn(a, "seconds"), WithoutColumn(b, "seconds"));
  EXPECT_FALSE(Contains(WithoutColumn(a, "seconds"), "seconds"));  // the helper did drop the column
  EXPECT_TRUE(Contains(WithoutColumn(a, "seconds"), "energy_drift"));
}

TEST_F(StudyCliTest, DivergedAndDriftedRowsAreReportedAndTheStudyStillSucceeds) {
  // euler at h = 0.01: beta = 400 holds the rod, beta = 0 lets it drift 1.5% off, beta = 1e8 runs away
  const std::string study =
      WriteStudy(R"({"/stabilization/beta": [400.0, 0.0, 1.0e8], "/simulation/integrator": ["euler"]})",
                 R"(["max_constraint_error"])");
  std::filesystem::create_directories(out_.Path("views"));
  out_.Write("views/2.js", "tetherStudyRow({});\n");  // an earlier run's view of the row that now diverges
  const Outcome run = Study(study, out_, " --threads 2");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> lines = Lines(ReadText(out_.Path("results.csv")));
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(CsvCells(lines[1]).back(), "ok") << lines[1];
  const std::vector<std::string> drifted = CsvCells(lines[2]);
  EXPECT_GT(std::stod(drifted[2]), 0.007) << lines[2];  // measured all the same
  EXPECT_EQ(drifted.back().rfind("drifted: t = ", 0), 0u) << lines[2];
  const std::vector<std::string> diverged = CsvCells(lines[3]);
  ASSERT_GE(diverged.size(), 4u) << lines[3];
  EXPECT_EQ(diverged[2], "nan") << lines[3];
  EXPECT_EQ(diverged[3].rfind("diverged", 0), 0u) << lines[3];
  const std::string summary = ReadText(out_.Path("summary.md"));
  for (const char* status : {"| ok |", "| drifted |", "| diverged |"})
    EXPECT_TRUE(Contains(summary, status)) << summary;
  ExpectFigure(out_.Path("max_constraint_error.png"));
#ifdef TETHER_HAVE_VIEWER
  // index.html, and a view of each run that finished: the ok and the drifted one, to their last state
  const std::string index = ReadText(out_.Path("index.html"));
  EXPECT_TRUE(Contains(index, R"("figures":["max_constraint_error.png"])")) << "the study's figure";
  EXPECT_TRUE(Contains(index, R"("status":"ok","values":[400.0,"euler"],"view":true)"));
  EXPECT_TRUE(Contains(index, R"("values":[100000000.0,"euler"],"view":false)"));
  for (const int row : {0, 1}) {
    const std::string view = ReadText(out_.Path("views/" + std::to_string(row) + ".js"));
    ASSERT_EQ(view.rfind("tetherStudyRow(", 0), 0u);
    const nlohmann::json data = nlohmann::json::parse(view.substr(15, view.size() - 15 - 3));
    EXPECT_EQ(data["row"], row);
    EXPECT_EQ(data["values"][1], "euler");
    EXPECT_DOUBLE_EQ(data["frames"]["times"].back().get<double>(), 0.5);  // the run's last state
    EXPECT_EQ(data["series"]["names"], nlohmann::json({"constraint_error", "energy"}));
  }
  EXPECT_FALSE(std::filesystem::exists(out_.Path("views/2.js")));  // a diverged run keeps no motion, nor an old one
#endif
}

TEST_F(StudyCliTest, ZeroThreadsExitsTwoNamingTheFlag) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01]})", R"(["seconds"])");
  const Outcome run = Study(study, out_, " --threads 0");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "--threads")) << run.err;
  EXPECT_EQ(run.out, "");
  EXPECT_TRUE(out_.Entries().empty());
}

TEST_F(StudyCliTest, BadStudyExitsTwoNamingTheFileAndPointerAndWritesNothing) {
  struct Case {
    std::string sweep, metrics;
    std::vector<std::string> named;
  };
  const std::vector<Case> cases = {
      {R"({"/simulation/step": [0.01]})", R"(["seconds", "accuracy"])", {"study.json", "/metrics/1"}},
      {R"({})", R"(["seconds"])", {"study.json", "/sweep"}},
      {R"({"/simulation/step": [0.01, -0.01]})", R"(["seconds"])", {"study.json", "row 1", "/simulation/step"}},
      // a pointer that cannot address the scene ("first" is no array index) is bad input too
      {R"({"/bodies/first/mass": [1.0]})", R"(["seconds"])", {"study.json", "/bodies/first/mass"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.sweep + " " + c.metrics);
    const Outcome run = Study(WriteStudy(c.sweep, c.metrics), out_);
    EXPECT_EQ(run.status, 2) << run.err;
    for (const std::string& part : c.named) EXPECT_TRUE(Contains(run.err, part)) << part << " in: " << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_TRUE(out_.Entries().empty()) << "no output on bad input";
  }
  // a missing scene file is named too
  const std::string study = folder_.Write(
      "missing.json", R"({"scene": "nowhere.json", "sweep": {"/simulation/step": [0.01]}, "metrics": ["seconds"]})");
  const Outcome run = Study(study, out_);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "nowhere.json")) << run.err;
  EXPECT_TRUE(Contains(run.err, "/scene")) << run.err;
}

}  // namespace
}  // namespace tether
