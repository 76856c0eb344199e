// The study runner in process (studies/include/tether/studies/study.h): ReadStudySpec validates STUDY.json and
// every combination of the sweep, naming the file and the JSON Pointer (and the row) at fault; RunStudy runs the
// cartesian product with the first swept pointer varying slowest, in the file's key order, measures each run
// against the reference motion, marks a diverged row with NaN metrics without touching the others, and resumes
// from results.partial.csv. Labelled scenes add a leading `scene` column; "tuned" runs the tuner's gains; the
// figures list is validated.
#include "tether/studies/study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/gain_tuning.h"
#include "tether/tuning/reference.h"

namespace tether {
namespace {

using testing::ReadText;
using testing::TempFolder;

// The acceptance checks' pendulum (a 1 kg bob on a 0.7 m rod released at rest from 60 degrees, exactly on the
// rod, so no assembly), rk4 at h = 0.01 with explicit Baumgarte gains stiff enough that euler at h = 0.01 stays
// within 1% of the rod (a run that drifts further is "drifted", not "ok"), for `duration` seconds.
std::string PendulumScene(double duration) {
  std::ostringstream text;
  text.precision(17);
  text << R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.01, "duration": )"
       << duration << R"(},
  "stabilization": {"method": "baumgarte", "alpha": 20.0, "beta": 400.0}})";
  return text.str();
}

// results.csv as lines of cells, quoted cells unquoted (the trailing newline ends the last line, it adds none).
std::vector<std::vector<std::string>> ReadCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(ReadText(path));
  for (std::string line; std::getline(in, line);) rows.push_back(testing::CsvCells(line));
  return rows;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

bool Exists(const std::string& path) { return std::filesystem::exists(path); }

class StudyTest : public ::testing::Test {
 protected:
  // Writes pendulum.json and study.json beside it; `sweep` and `metrics` are JSON text.
  std::string WriteStudy(const std::string& sweep, const std::string& metrics, double duration = 0.5) const {
    folder_.Write("pendulum.json", PendulumScene(duration));
    return folder_.Write("study.json",
                         R"({"scene": "pendulum.json", "sweep": )" + sweep + R"(, "metrics": )" + metrics + "}");
  }

  // Runs the study into `out` on `threads` threads, ignoring the progress reports.
  static std::vector<StudyRow> Run(const std::string& study, const TempFolder& out, int threads = 1) {
    return RunStudy(ReadStudySpec(study), out.path(), threads, false, [](int, int, double) {});
  }

  // ReadStudySpec(study) must throw InputError whose message contains every one of `parts`.
  static void ExpectInputError(const std::string& study, std::initializer_list<std::string> parts) {
    try {
      ReadStudySpec(study);
      ADD_FAILURE() << "no InputError; expected one naming " << *parts.begin();
    } catch (const InputError& e) {
      for (const std::string& part : parts) EXPECT_TRUE(Contains(e.what(), part)) << "'" << part << "' in: " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "expected an InputError, got another exception: " << e.what();
    }
  }

  TempFolder folder_{"tether_study"};
  TempFolder out_{"tether_study_out"};
};

TEST_F(StudyTest, RowsAreTheCartesianProductWithTheFirstPointerSlowestInTheFilesKeyOrder) {
  // keys deliberately not in alphabetical order (nor reverse order)
  const std::string study = WriteStudy(
      R"({"/simulation/step": [0.01, 0.005], "/simulation/integrator": ["rk4", "euler"], "/bodies/0/mass": [1.0, 2.0, 3.0]})",
      R"(["max_constraint_error"])");
  const StudySpec spec = ReadStudySpec(study);
  const std::vector<std::string> pointers = {"/simulation/step", "/simulation/integrator", "/bodies/0/mass"};
  EXPECT_EQ(spec.pointers, pointers);
  EXPECT_EQ(spec.metrics, std::vector<std::string>{"max_constraint_error"});
  ASSERT_EQ(RowCount(spec), 12);

  const std::vector<StudyRow> rows = RunStudy(spec, out_.path(), 1, false, [](int, int, double) {});
  ASSERT_EQ(rows.size(), 12u);
  const std::vector<double> steps = {0.01, 0.005}, masses = {1.0, 2.0, 3.0};
  const std::vector<std::string> integrators = {"rk4", "euler"};
  const auto csv = ReadCsv(out_.Path("results.csv"));
  ASSERT_EQ(csv.size(), 13u);  // header + a row per combination
  EXPECT_EQ(csv[0], (std::vector<std::string>{"/simulation/step", "/simulation/integrator", "/bodies/0/mass",
                                               "max_constraint_error", "status"}));
  for (int i = 0; i < 12; ++i) {
    const double step = steps[i / 6], mass = masses[i % 3];
    const std::string integrator = integrators[(i / 3) % 2];
    ASSERT_EQ(rows[i].values.size(), 3u);
    EXPECT_EQ(rows[i].values[0].get<double>(), step) << "row " << i;
    EXPECT_EQ(rows[i].values[1].get<std::string>(), integrator) << "row " << i;
    EXPECT_EQ(rows[i].values[2].get<double>(), mass) << "row " << i;
    EXPECT_EQ(rows[i].status, "ok") << "row " << i;
    ASSERT_EQ(csv[i + 1].size(), 5u) << "row " << i;
    EXPECT_EQ(std::stod(csv[i + 1][0]), step) << "row " << i;
    EXPECT_EQ(csv[i + 1][1], integrator) << "row " << i;
    EXPECT_EQ(std::stod(csv[i + 1][2]), mass) << "row " << i;
    EXPECT_EQ(csv[i + 1][4], "ok") << "row " << i;
    // the file carries the same metric the function returns (17 significant digits: exact round trip)
    EXPECT_EQ(std::stod(csv[i + 1][3]), rows[i].metrics[0]) << "row " << i;
  }
  // the swept values reach the scene: euler drifts off the rod far more than rk4 at the same step
  // (rows 0 and 3: h = 0.01, mass 1, rk4 then euler)
  EXPECT_GT(rows[3].metrics[0], 10.0 * rows[0].metrics[0]);
  EXPECT_FALSE(Exists(out_.Path("results.partial.csv")));
}

TEST_F(StudyTest, MetricsMatchTheirDefinitionsAndRankTheIntegratorsByAccuracy) {
  const std::string study =
      WriteStudy(R"({"/simulation/integrator": ["rk4", "euler"], "/simulation/step": [0.01, 0.001]})",
                 R"(["rms_position_error", "max_constraint_error", "energy_drift", "seconds"])", 1.0);
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 4u);  // rk4 0.01, rk4 0.001, euler 0.01, euler 0.001
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].status, "ok") << "row " << i;
    ASSERT_EQ(rows[i].metrics.size(), 4u);
    for (int m = 0; m < 3; ++m) {
      EXPECT_TRUE(std::isfinite(rows[i].metrics[m])) << "row " << i << " metric " << m;
      EXPECT_GE(rows[i].metrics[m], 0.0) << "row " << i << " metric " << m;
    }
    EXPECT_GT(rows[i].metrics[3], 0.0) << "row " << i << ": seconds";
    EXPECT_LT(rows[i].metrics[3], 10.0) << "row " << i << ": seconds (a 1 s pendulum takes milliseconds)";
  }
  const double rk4_fine = rows[1].metrics[0], rk4_coarse = rows[0].metrics[0], euler_coarse = rows[2].metrics[0];
  // accuracy: rk4 h=1e-3 < rk4 h=1e-2 < euler h=1e-2, each by a clear margin (rk4 is fourth order, euler first)
  EXPECT_LT(rk4_fine, 0.1 * rk4_coarse) << rk4_fine << " vs " << rk4_coarse;
  EXPECT_LT(rk4_coarse, 0.1 * euler_coarse) << rk4_coarse << " vs " << euler_coarse;
  // euler converges too: ten times smaller step, a smaller error
  EXPECT_LT(rows[3].metrics[0], euler_coarse);

  // row 0 recomputed by hand from the definitions in study.h; results.csv prints 17 digits, so the values
  // agree to round-off (1e-12 relative, allowing for a different summation order)
  Model<double> model = ParseScene(ParseJsonText(PendulumScene(1.0), "p.json"), "p.json").model;
  std::vector<Eigen::VectorXd> q;
  double worst = 0.0, drift = 0.0, energy0 = NAN;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    if (q.empty()) energy0 = s.energy;
    q.push_back(s.q);
    worst = std::max(worst, s.constraint_error);
    drift = std::max(drift, std::abs(s.energy - energy0));
  });
  Trajectory<double> run;
  run.q = q;
  const double rms = RmsPositionError(model, ComputeReference(model), run);
  EXPECT_NEAR(rows[0].metrics[0], rms, 1e-12 * rms);
  EXPECT_NEAR(rows[0].metrics[1], worst, 1e-12 * worst + 1e-300);
  const double energy_drift = drift / std::max(std::abs(energy0), 1.0);
  EXPECT_NEAR(rows[0].metrics[2], energy_drift, 1e-12 * energy_drift + 1e-300);
  // and euler's energy error dwarfs rk4's at the same step
  EXPECT_GT(rows[2].metrics[2], 10.0 * rows[0].metrics[2]);
}

// `events` counts a run's joint-limit events: the README's rod against its stop (docs/examples/limits), four impacts
// in 3 s at e = 0.75, and at e = 0.5 as many as a plain run of that scene reports.
TEST_F(StudyTest, EventsCountsTheJointLimitsImpactsAndReleases) {
  nlohmann::json scene =
      nlohmann::json::parse(ReadText(std::string(TETHER_SOURCE_DIR) + "/docs/examples/limits/stop.json"));
  folder_.Write("stop.json", scene.dump());
  const std::string study = folder_.Write(
      "study.json",
      R"({"scene": "stop.json", "sweep": {"/constraints/0/restitution": [0.5, 0.75]}, "metrics": ["events"]})");
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 2u);
  scene["constraints"][0]["restitution"] = 0.5;
  const RunReport half =
      Simulate<double>(ParseScene(scene, "stop.json").model, RunOptions{}, [](const Sample<double>&) {});
  EXPECT_EQ(rows[0].metrics[0], static_cast<double>(half.events.size()));
  EXPECT_EQ(rows[1].metrics[0], 4.0);
}

TEST_F(StudyTest, DivergedRowHasNanMetricsAndItsStatusWhileTheOthersAreUnaffected) {
  // euler at h = 0.01 with beta = 1e8: h^2 beta = 1e4, the Baumgarte term blows up within a few steps
  const std::string study =
      WriteStudy(R"({"/simulation/integrator": ["euler"], "/stabilization/beta": [400.0, 1.0e8]})",
                 R"(["rms_position_error", "max_constraint_error", "energy_drift"])");
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "ok");
  EXPECT_EQ(rows[1].status.rfind("diverged", 0), 0u) << rows[1].status;
  for (int m = 0; m < 3; ++m) {
    EXPECT_TRUE(std::isnan(rows[1].metrics[m])) << "metric " << m << " = " << rows[1].metrics[m];
    EXPECT_TRUE(std::isfinite(rows[0].metrics[m])) << "metric " << m;
  }
  const auto csv = ReadCsv(out_.Path("results.csv"));
  ASSERT_EQ(csv.size(), 3u);
  ASSERT_GE(csv[2].size(), 6u);
  EXPECT_EQ(csv[2][2], "nan");
  EXPECT_EQ(csv[2][3], "nan");
  EXPECT_EQ(csv[2][4], "nan");
  EXPECT_EQ(csv[2][5].rfind("diverged", 0), 0u) << csv[2][5];

  // the healthy row is exactly what the same study without the diverging value gives (runs are deterministic)
  folder_.Write("alone.json", R"({"scene": "pendulum.json", "sweep": {"/simulation/integrator": ["euler"],
    "/stabilization/beta": [400.0]}, "metrics": ["rms_position_error", "max_constraint_error", "energy_drift"]})");
  TempFolder alone_out("tether_study_alone");
  const std::vector<StudyRow> alone = Run(folder_.Path("alone.json"), alone_out);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(alone[0].status, "ok");
  for (int m = 0; m < 3; ++m) EXPECT_EQ(rows[0].metrics[m], alone[0].metrics[m]) << "metric " << m;
}

TEST_F(StudyTest, ARowWhoseConstraintsDriftedIsMeasuredButNotOk) {
  // euler without the position gain (beta = 0) ends 5 cm off its 0.7 m rod: within the length scale, no divergence
  const std::string study = WriteStudy(R"({"/simulation/integrator": ["euler"], "/stabilization/beta": [400.0, 0.0]})",
                                       R"(["max_constraint_error"])", 2.0);
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "ok");
  EXPECT_EQ(rows[1].status.rfind("drifted: t = ", 0), 0u) << rows[1].status;
  EXPECT_TRUE(Contains(rows[1].status, "of the scene's length scale")) << rows[1].status;
  EXPECT_GT(rows[1].metrics[0], 0.01 * 0.7);  // measured all the same
  EXPECT_EQ(ReadCsv(out_.Path("results.csv"))[2].back().rfind("drifted", 0), 0u);
}

TEST_F(StudyTest, ThreadCountDoesNotChangeTheRowsInProcess) {
  const std::string study = WriteStudy(R"({"/stabilization/alpha": [5.0, 10.0, 20.0], "/simulation/step": [0.01, 0.002]})",
                                       R"(["max_constraint_error", "rms_position_error"])");
  TempFolder out2("tether_study_out2");
  const std::vector<StudyRow> one = Run(study, out_, 1), three = Run(study, out2, 3);
  ASSERT_EQ(one.size(), 6u);
  ASSERT_EQ(three.size(), 6u);
  for (size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].values, three[i].values) << "row " << i;
    EXPECT_EQ(one[i].metrics, three[i].metrics) << "row " << i;  // bit for bit
    EXPECT_EQ(one[i].status, three[i].status) << "row " << i;
  }
  EXPECT_EQ(ReadText(out_.Path("results.csv")), ReadText(out2.Path("results.csv")));
}

TEST_F(StudyTest, ResumesFromThePartialFileWithoutRedoingFinishedRows) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, 0.005, 0.002]})",
                                       R"(["rms_position_error", "max_constraint_error"])");
  // an interrupted run finished row 1; its (fake, recognisable) metrics must survive untouched; the line of
  // row 2 was torn (no line end): that row runs again
  out_.Write("results.partial.csv", "# tether study " + StudyFingerprint(ReadStudySpec(study)) +
                                        "\nindex,/simulation/step,rms_position_error,max_constraint_error,status\n"
                                        "1,0.005,12345.5,678.25,ok\n2,0.002,1e-9");
  std::vector<int> done_reports;
  const std::vector<StudyRow> rows =
      RunStudy(ReadStudySpec(study), out_.path(), 1, false, [&](int done, int total, double eta) {
        EXPECT_EQ(total, 3);
        EXPECT_GE(eta, 0.0);
        done_reports.push_back(done);
      });
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].metrics, (std::vector<double>{12345.5, 678.25}));
  EXPECT_EQ(rows[1].status, "ok");
  for (int i : {0, 2}) {  // computed now: real, small errors (a 0.7 m pendulum stays well within 0.1 m)
    EXPECT_EQ(rows[i].status, "ok") << "row " << i;
    for (double m : rows[i].metrics) {
      EXPECT_TRUE(std::isfinite(m)) << "row " << i;
      EXPECT_GE(m, 0.0) << "row " << i;
      EXPECT_LT(m, 0.1) << "row " << i;
    }
  }
  // only the two missing rows ran, and the progress counts on from the finished one
  EXPECT_EQ(done_reports, (std::vector<int>{2, 3}));

  EXPECT_FALSE(Exists(out_.Path("results.partial.csv")));
  const auto csv = ReadCsv(out_.Path("results.csv"));
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[0], (std::vector<std::string>{"/simulation/step", "rms_position_error", "max_constraint_error", "status"}));
  EXPECT_EQ(csv[2], (std::vector<std::string>{"0.005", "12345.5", "678.25", "ok"}));
  for (int i : {1, 3}) {
    ASSERT_EQ(csv[i].size(), 4u);
    EXPECT_EQ(std::stod(csv[i][1]), rows[i - 1].metrics[0]);
  }

  // the computed rows equal those of a fresh run
  TempFolder fresh_out("tether_study_fresh");
  const std::vector<StudyRow> fresh = Run(study, fresh_out);
  EXPECT_EQ(rows[0].metrics, fresh[0].metrics);
  EXPECT_EQ(rows[2].metrics, fresh[2].metrics);
  EXPECT_NE(fresh[1].metrics[0], 12345.5);
}

TEST_F(StudyTest, PartialResultsOfAnotherStudyAreRefusedUnlessRestarted) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, 0.005]})", R"(["rms_position_error"])");
  const std::string header = "index,/simulation/step,rms_position_error,status\n";
  // the same header, but a fingerprint that is not this study's (its scene changed since), and an old file
  // without a fingerprint: neither is resumed, and neither is thrown away unasked
  for (const std::string& stale : {"# tether study 0123456789abcdef\n" + header + "1,0.005,12345.5,ok\n",
                                   header + "1,0.005,12345.5,ok\n"}) {
    const std::string partial = out_.Write("results.partial.csv", stale);
    try {
      RunStudy(ReadStudySpec(study), out_.path(), 1, false, [](int, int, double) {});
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--out"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--restart"), std::string::npos) << e.what();
    }
    EXPECT_EQ(ReadText(partial), stale);
  }
  const std::vector<StudyRow> rows = RunStudy(ReadStudySpec(study), out_.path(), 1, true, [](int, int, double) {});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].status, "ok");
  EXPECT_LT(rows[1].metrics[0], 0.1);  // computed, not the stale 12345.5
  EXPECT_FALSE(Exists(out_.Path("results.partial.csv")));
}

TEST_F(StudyTest, AFinishedStudyIsReadBackNotRunAgain) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, 0.005]})", R"(["seconds"])");
  const std::vector<StudyRow> first = Run(study, out_);
  const std::string results = ReadText(out_.Path("results.csv"));
  int reports = 0;
  const std::vector<StudyRow> again =
      RunStudy(ReadStudySpec(study), out_.path(), 1, false, [&](int, int, double) { ++reports; });
  EXPECT_EQ(reports, 0);  // nothing ran
  ASSERT_EQ(again.size(), first.size());
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(again[i].metrics, first[i].metrics);  // wall times too
  EXPECT_EQ(ReadText(out_.Path("results.csv")), results);
  // --restart runs it again
  RunStudy(ReadStudySpec(study), out_.path(), 1, true, [&](int, int, double) { ++reports; });
  EXPECT_EQ(reports, 2);
}

// A clean clone's studies/accuracy/results has results.csv without a fingerprint (it is not committed): running
// the study into that folder again rewrote the shipped results silently.
TEST_F(StudyTest, ResultsOfAnotherStudyAreNeverReplacedWithoutRestart) {
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, 0.005]})", R"(["seconds"])");
  Run(study, out_);
  const std::string results = ReadText(out_.Path("results.csv"));
  std::filesystem::remove(out_.Path("results.fingerprint"));  // as shipped
  const std::string other = folder_.Write(
      "other.json", R"({"scene": "pendulum.json", "sweep": {"/simulation/step": [0.02]}, "metrics": ["seconds"]})");
  for (const std::string& which : {study, other}) {
    try {
      Run(which, out_);
      ADD_FAILURE() << "no InputError for " << which;
    } catch (const InputError& e) {
      for (const char* part : {"--out", "results.csv", "another study", "--restart"})
        EXPECT_TRUE(Contains(e.what(), part)) << part << " in: " << e.what();
    }
    EXPECT_EQ(ReadText(out_.Path("results.csv")), results);
  }
  EXPECT_EQ(RunStudy(ReadStudySpec(other), out_.path(), 1, true, [](int, int, double) {}).size(), 1u);
}

TEST_F(StudyTest, ValuesWithCommasAreQuotedCellsOfTheResults) {
  const std::string study = WriteStudy(R"({"/bodies/0/position": [[0.6, -0.35], [0.35, -0.6]]})", R"(["seconds"])");
  Run(study, out_);
  const auto csv = ReadCsv(out_.Path("results.csv"));
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[1][0], "[0.6,-0.35]");
  EXPECT_EQ(csv[2][0], "[0.35,-0.6]");
  EXPECT_EQ(csv[1].size(), 3u);
  EXPECT_EQ(csv[1][2], "ok");
}

// --- errors: InputError naming the study file and the JSON Pointer (and the row for a bad combination) ---

TEST_F(StudyTest, UnknownTopLevelKeyIsAnInputError) {
  folder_.Write("pendulum.json", PendulumScene(0.5));
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/step": [0.01]}, "metrics": ["seconds"], "metric": ["rms_position_error"]})");
  ExpectInputError(study, {study, "/metric", "unknown"});
}

TEST_F(StudyTest, MissingSceneFileIsAnInputError) {
  const std::string study = folder_.Write(
      "study.json", R"({"scene": "no_such_scene.json", "sweep": {"/simulation/step": [0.01]}, "metrics": ["seconds"]})");
  ExpectInputError(study, {"no_such_scene.json", "/scene", "study.json"});
}

TEST_F(StudyTest, SweepThatIsNotAnObjectOrIsEmptyIsAnInputError) {
  for (const std::string sweep : {R"([0.01, 0.02])", R"("/simulation/step")", R"({})"}) {
    SCOPED_TRACE(sweep);
    ExpectInputError(WriteStudy(sweep, R"(["seconds"])"), {folder_.Path("study.json"), "/sweep"});
  }
}

TEST_F(StudyTest, EmptyOrNonArrayValueListIsAnInputErrorNamingThePointer) {
  for (const std::string values : {"[]", "0.01"}) {
    SCOPED_TRACE(values);
    const std::string study = WriteStudy(R"({"/simulation/step": [0.01], "/stabilization/beta": )" + values + "}",
                                         R"(["seconds"])");
    try {
      ReadStudySpec(study);
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_TRUE(Contains(message, study)) << message;
      EXPECT_TRUE(Contains(message, "/sweep")) << message;
      // the swept pointer, as written or escaped per RFC 6901 inside /sweep
      EXPECT_TRUE(Contains(message, "/stabilization/beta") || Contains(message, "~1stabilization~1beta")) << message;
      EXPECT_FALSE(Contains(message, "/simulation/step")) << message;  // the good entry is not blamed
    }
  }
}

TEST_F(StudyTest, UnknownOrMissingMetricIsAnInputError) {
  ExpectInputError(WriteStudy(R"({"/simulation/step": [0.01]})", R"(["rms_position_error", "speed"])"),
                   {folder_.Path("study.json"), "/metrics/1", "speed"});
  ExpectInputError(WriteStudy(R"({"/simulation/step": [0.01]})", R"([])"), {folder_.Path("study.json"), "/metrics"});
}

TEST_F(StudyTest, SweptValueThatMakesTheSceneInvalidIsAnInputErrorNamingItsRow) {
  // row 0 is fine, row 1 has a negative step: caught before any run, with the row and the pointer
  const std::string study = WriteStudy(R"({"/simulation/step": [0.01, -0.01]})", R"(["seconds"])");
  ExpectInputError(study, {study, "row 1", "/simulation/step"});
  // an integrator name that does not exist (row 1 = step 0.01 with verlet: the second pointer varies fastest)
  ExpectInputError(WriteStudy(R"({"/simulation/step": [0.01, 0.005], "/simulation/integrator": ["rk4", "verlet"]})",
                              R"(["seconds"])"),
                   {folder_.Path("study.json"), "row 1", "/simulation/integrator"});
  EXPECT_FALSE(Exists(out_.Path("results.csv")));
}

TEST_F(StudyTest, SweptPointerThatCannotAddressTheSceneIsAnInputError) {
  // "first" is not an array index of /bodies, and a number has no members: bad input (InputError), never
  // another exception (which the command line would report as a failed run, exit status 1)
  for (const std::string pointer : {"/bodies/first/mass", "/bodies/0/mass/x"}) {
    SCOPED_TRACE(pointer);
    const std::string study = WriteStudy(R"({")" + pointer + R"(": [1.0, 2.0]})", R"(["seconds"])");
    ExpectInputError(study, {study, pointer});
  }
}

TEST_F(StudyTest, SweptPointerPastTheEndOfAnArrayIsAnInputErrorNamingThatPointer) {
  // the scene has one body: /bodies/3 does not exist, and writing there must not invent bodies 1 to 3; the
  // message must blame the swept pointer, not a null body the writing created
  const std::string study = WriteStudy(R"({"/bodies/3/mass": [1.0]})", R"(["seconds"])");
  ExpectInputError(study, {study, "/bodies/3/mass"});
}

// A swept pointer that ends in /* writes its value into every element of that array (as --param's wildcard names
// every element); on anything but a non-empty array it is an InputError naming the swept entry.
TEST_F(StudyTest, AWildcardSweepWritesEveryElementOfItsArray) {
  const std::string study = WriteStudy(R"({"/effects/0/acceleration/*": [-2.0, -4.0]})", R"(["seconds"])");
  const StudySpec spec = ReadStudySpec(study);
  ASSERT_EQ(RowCount(spec), 2);
  for (int row = 0; row < 2; ++row) {
    const RowScene scene = SceneOfRow(spec, Combination(spec, row), "row " + std::to_string(row));
    ASSERT_EQ(scene.model.gravity.size(), 1u);
    EXPECT_EQ(scene.model.gravity[0].acceleration, Vec3<double>(-2.0 * (row + 1), -2.0 * (row + 1), 0.0));
  }
  for (const std::string pointer : {"/bodies/0/mass/*", "/bodies/5/*"}) {
    SCOPED_TRACE(pointer);
    const std::string bad = WriteStudy(R"({")" + pointer + R"(": [1.0]})", R"(["seconds"])");
    ExpectInputError(bad, {bad, "/sweep/", "not a non-empty array"});
  }
}

// "ties" in the study file: numbers that follow the swept ones row by row (as --tie); a tie that does not resolve,
// or that sets a swept number, is an InputError naming the study file and /ties.
TEST_F(StudyTest, TiedNumbersFollowTheSweptOnes) {
  folder_.Write("pendulum.json", PendulumScene(0.5));
  const std::string study = folder_.Write(
      "study.json", R"({"scene": "pendulum.json", "sweep": {"/stabilization/beta": [25.0, 50.0]},
                        "ties": ["/stabilization/alpha={/stabilization/beta}/2.5"], "metrics": ["seconds"]})");
  const StudySpec spec = ReadStudySpec(study);
  for (int row = 0; row < 2; ++row) {
    const RowScene scene = SceneOfRow(spec, Combination(spec, row), "row " + std::to_string(row));
    EXPECT_DOUBLE_EQ(scene.model.stabilization.alpha, 10.0 * (row + 1));
  }
  const std::string bad = folder_.Write(
      "bad.json", R"({"scene": "pendulum.json", "sweep": {"/stabilization/beta": [25.0]},
                      "ties": ["/stabilization/alpha={/bodies/3/mass}"], "metrics": ["seconds"]})");
  ExpectInputError(bad, {bad, "/ties", "/bodies/3/mass"});
  // a tie on what the sweep sets would label rows with values they were not run with
  for (const char* tie : {"/stabilization/beta=5", "/stabilization/beta/*={/stabilization/alpha}"}) {
    const std::string clash = folder_.Write(
        "clash.json",
        std::string(R"({"scene": "pendulum.json", "sweep": {"/stabilization/beta": [25.0]}, "ties": [")") + tie +
            R"("], "metrics": ["seconds"]})");
    ExpectInputError(clash, {clash, "/ties/0", "which the sweep sets", "/sweep/~1stabilization~1beta"});
  }
}

TEST_F(StudyTest, EnergyDriftIsMeasuredWithoutTheReferenceMetric) {
  // euler at h = 0.01 gains energy visibly; the row must show it even when no reference is asked for
  const std::string study = WriteStudy(R"({"/simulation/integrator": ["euler"]})", R"(["energy_drift"])", 1.0);
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_GT(rows[0].metrics[0], 1e-4);
}

TEST_F(StudyTest, TunedRowsRunWithTheTunersGainsAndReportTheGainsInUse) {
  // the pendulum without gains: "baumgarte" takes the default rule's
  nlohmann::json scene = ParseJsonText(PendulumScene(1.0), "p.json");
  scene.erase("stabilization");
  folder_.Write("pendulum.json", scene.dump());
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/stabilization/method": ["none", "baumgarte", "tuned", "projection"]},
    "metrics": ["alpha", "beta", "seconds", "seconds_per_simulated_second"]})");
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 4u);
  const Model<double> model = ParseScene(scene, "p.json").model;
  const TuneResult tuned = TuneGains(model, TuneSettings{});
  const Gains rule = DefaultGains(Integrator::kRk4, 0.01);
  const std::vector<std::pair<double, double>> gains = {
      {0.0, 0.0}, {rule.alpha, rule.beta}, {tuned.alpha, tuned.beta}, {0.0, 0.0}};
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].status, "ok") << "row " << i;
    EXPECT_NEAR(rows[i].metrics[0], gains[i].first, 1e-9 * (1.0 + gains[i].first)) << "row " << i;
    EXPECT_NEAR(rows[i].metrics[1], gains[i].second, 1e-9 * (1.0 + gains[i].second)) << "row " << i;
    // the scene lasts 1 s: seconds per simulated second equals the seconds (to the 17 digits printed)
    EXPECT_NEAR(rows[i].metrics[3], rows[i].metrics[2], 1e-15) << "row " << i;
  }
  EXPECT_GT(tuned.alpha, 0.0);
}

TEST_F(StudyTest, LabelledScenesMakeALeadingSceneColumnAndEachRowRunsItsScene) {
  folder_.Write("short.json", PendulumScene(0.2));
  folder_.Write("long.json", PendulumScene(0.6));
  const std::string study = folder_.Write("scenes.json", R"({"scene": {"short": "short.json", "long": "long.json"},
    "sweep": {"/simulation/integrator": ["rk4", "euler"]}, "metrics": ["max_constraint_error"]})");
  const StudySpec spec = ReadStudySpec(study);
  EXPECT_EQ(spec.pointers, (std::vector<std::string>{"scene", "/simulation/integrator"}));
  const std::vector<StudyRow> rows = Run(study, out_);
  ASSERT_EQ(rows.size(), 4u);
  const auto csv = ReadCsv(out_.Path("results.csv"));
  ASSERT_EQ(csv.size(), 5u);
  EXPECT_EQ(csv[0][0], "scene");
  const std::vector<std::string> scenes = {"short", "short", "long", "long"};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(csv[i + 1][0], scenes[i]) << "row " << i;
  // each row ran its own scene: euler's violation grows with the duration
  EXPECT_GT(rows[3].metrics[0], rows[1].metrics[0]);
}

TEST_F(StudyTest, BadFiguresAreInputErrorsNamingTheFigure) {
  folder_.Write("pendulum.json", PendulumScene(0.5));
  const struct {
    std::string figures;
    std::string part;
  } cases[] = {
      {R"([{"type": "contour"}])", "/figures/0/type"},
      {R"([{"type": "lines"}, {"type": "pareto", "x": "seconds", "y": "accuracy"}])", "/figures/1/y"},
      {R"([{"type": "pareto", "x": "seconds"}])", "/figures/0/y"},
      {R"([{"type": "gain_map", "color": "seconds"}])", "/figures/0"},
      {R"([{"type": "lines", "color": "seconds"}])", "/figures/0/color"},
      {R"([])", "/figures"},
  };
  for (const auto& c : cases) {
    const std::string study = folder_.Write("figures.json", R"({"scene": "pendulum.json",
      "sweep": {"/simulation/step": [0.01]}, "metrics": ["seconds"], "figures": )" + c.figures + "}");
    ExpectInputError(study, {"figures.json", c.part});
  }
}

}  // namespace
}  // namespace tether
