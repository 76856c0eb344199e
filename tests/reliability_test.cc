// The reliability suite (issue 15): adversarial invocations of the real binary, each with the exit status it
// must give, the words its message must hold (the file, the JSON Pointer, the flag at fault) and, after it, no
// temporary file left in the folder and no input damaged. The reproducers of the issue come first, quoted in
// the case names; docs/robustness.md lists the suite with its counts.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using testing::Outcome;
using testing::ReadText;
using testing::TempFolder;

const std::string kSource = TETHER_SOURCE_DIR;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The acceptance checks' pendulum, for 1 s.
const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 1.0}})";

// A sweep of `count` values of the step, as JSON text.
std::string Steps(int count) {
  std::string values = "[";
  for (int k = 0; k < count; ++k) values += (k ? "," : "") + std::to_string(0.001 + 1e-9 * k);
  return values + "]";
}

// `count` particles on rods to one hub particle, as JSON text.
std::string Star(int count) {
  nlohmann::json bodies = {{{"name", "hub"}, {"type", "particle"}, {"mass", 1.0}, {"position", {0.0, 0.0, 0.0}}}};
  nlohmann::json constraints = nlohmann::json::array();
  for (int k = 0; k < count; ++k) {
    const std::string name = "p" + std::to_string(k);
    const double angle = 2 * M_PI * k / count;
    bodies.push_back({{"name", name},
                      {"type", "particle"},
                      {"mass", 0.01},
                      {"position", {std::cos(angle), std::sin(angle), 0.1 * (k % 7)}}});
    constraints.push_back({{"type", "distance"}, {"bodies", {"hub", name}}});
  }
  return nlohmann::json{{"dimension", 3}, {"bodies", bodies}, {"constraints", constraints}}.dump();
}

struct Invocation {
  const char* name;
  std::string args;  // {dir}: the test's folder; {src}: the source tree
  int status;
  std::vector<std::string> messages;  // each must appear on stderr
  std::string launcher = "";          // what runs the binary (a shell that redirects its output, say)
};

std::string Expand(std::string text, const std::string& dir) {
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{dir}", dir}, {"{src}", kSource}}) {
    for (size_t at; (at = text.find(key)) != std::string::npos;) text.replace(at, key.size(), value);
  }
  return text;
}

std::string Repeated(const std::string& text, int times) {
  std::string out;
  for (int k = 0; k < times; ++k) out += text;
  return out;
}

class Reliability : public ::testing::TestWithParam<Invocation> {
 protected:
  void SetUp() override {
    folder_.Write("pendulum.json", kPendulum);
    folder_.Write("duplicate_key.json", R"({"dimension": 2, "bodies": [{"name": "a", "type": "particle",
      "mass": 1.0, "mass": 2.0, "position": [0, 0]}]})");
    folder_.Write("late_row.csv", "t,bob.x\n0,0.6\n0.5,0.1\n1.000000000000005,0.3\n");
    folder_.Write("on_time.csv", "t,bob.x\n0,0.6\n0.5,0.1\n1,0.3\n");
    folder_.Write("too_late.csv", "t,bob.x\n0,0.6\n1.001,0.3\n");
    folder_.Write("huge_study.json", R"({"scene": "pendulum.json", "sweep": {"/simulation/step": )" + Steps(65536) +
                                         R"(, "/simulation/duration": )" + Steps(65536) + R"(}, "metrics": ["seconds"]})");
    folder_.Write("empty_token_study.json", R"({"scene": "pendulum.json", "sweep": {"/nothing//x": [1, 2]},
      "metrics": ["seconds"]})");  // a fuzzer's finding: the JSON library refused the path uncaught
    folder_.Write("empty_cells.csv", "t,bob.x\n0,\n0.5,\n");
    std::filesystem::create_symlink("/dev/zero", folder_.Path("zero.urdf"));
    folder_.Write("nested.urdf",
                  "<robot name=\"x\">" + Repeated("<a>", 100000) + Repeated("</a>", 100000) + "</robot>");
    folder_.Write("hub.json", Star(2049));
    folder_.Write("small_study.json",
                  R"({"scene": "pendulum.json", "sweep": {"/simulation/step": [0.01]}, "metrics": ["seconds"]})");
    folder_.Write("unassemblable.json", R"({"dimension": 2,
      "bodies": [{"name": "p", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
      "constraints": [{"type": "distance", "bodies": ["world", "p"], "length": 1.0},
                      {"type": "distance", "bodies": ["world", "p"], "length": 3.0}]})");
  }

  TempFolder folder_{"tether_reliability"};
};

TEST_P(Reliability, ExitsWithItsStatusAndMessageAndLeavesNoTemporaryFile) {
  const Invocation& c = GetParam();
  const std::string before = ReadText(folder_.Path("pendulum.json"));
  const Outcome run = testing::RunTether(Expand(c.args, folder_.path()), folder_, c.launcher);
  EXPECT_EQ(run.status, c.status) << c.args << "\n" << run.err;
  for (const std::string& message : c.messages) EXPECT_TRUE(Contains(run.err, message)) << message << "\n" << run.err;
  for (const std::string& name : folder_.Entries()) EXPECT_FALSE(Contains(name, ".partial")) << name;
  EXPECT_EQ(ReadText(folder_.Path("pendulum.json")), before);  // no input damaged
  if (c.status != 0 && Contains(c.args, "-o '{dir}/out")) EXPECT_FALSE(std::filesystem::exists(folder_.Path("out.csv")));
}

INSTANTIATE_TEST_SUITE_P(
    Issue15, Reliability,
    ::testing::Values(
        // no false success
        Invocation{"chain20_blowing_up_on_its_last_step",
                   "simulate '{src}/scenes/chain20.json' --step 0.01 --duration 2 -o '{dir}/out.csv'",
                   1,
                   {"diverged at t = 2 s", "/constraints/"}},
        Invocation{"a_step_of_1e_12_for_0_01_s",
                   "simulate '{dir}/pendulum.json' --step 1e-12 --duration 0.01",
                   2,
                   {"--duration/--step", "more than a run may take"}},
        Invocation{"a_duration_of_3e6_s", "simulate '{dir}/pendulum.json' --duration 3e6", 2, {"--duration", "steps"}},
        Invocation{"two_sweeps_of_65536_values",
                   "study '{dir}/huge_study.json' --out '{dir}/huge'",
                   2,
                   {"huge_study.json", "/sweep/~1simulation~1duration", "1000000"}},
        Invocation{"a_sweep_pointer_with_an_empty_token",
                   "study '{dir}/empty_token_study.json' --out '{dir}/s'",
                   2,
                   {"empty_token_study.json", "/sweep/~1nothing~1~1x", "cannot be written into the scene"}},
        Invocation{"a_data_row_past_the_end_beyond_rounding",
                   "gradient '{dir}/pendulum.json' --data '{dir}/too_late.csv' --param /bodies/0/mass",
                   2,
                   {"too_late.csv", "line 3", "1.0009999999999999"}},
        Invocation{"a_scene_that_cannot_be_assembled",
                   "simulate '{dir}/unassemblable.json' -o '{dir}/out.csv'",
                   2,
                   {"unassemblable.json", "cannot be assembled"}},
        Invocation{"check_on_a_scene_that_cannot_be_assembled", "check '{dir}/unassemblable.json'", 1, {}},
        Invocation{
            "the_readme_identification_with_one_segment",
            "identify '{src}/docs/examples/identify/guess.json' --data '{src}/docs/examples/identify/recording.csv' "
            "--param /bodies/1/mass --segments 1 -o '{dir}/out.json'",
            1,
            {"far above the noise", "the identification failed", "no scene was written"}},
        // no crash
        Invocation{
            "nlopt_LN_AUGLAG", "tune '{dir}/pendulum.json' --optimizer nlopt:LN_AUGLAG --max-evaluations 20", 0, {}},
        Invocation{"nlopt_GD_STOGO_missing_from_the_build",
                   "tune '{dir}/pendulum.json' --optimizer nlopt:GD_STOGO",
                   2,
                   {"--optimizer", "GD_STOGO"}},
        Invocation{
            "an_unknown_nlopt_name", "tune '{dir}/pendulum.json' --optimizer nlopt:LN_NOTHING", 2, {"--optimizer"}},
        Invocation{
            "zero_threads", "study '{src}/studies/accuracy/study.json' --out '{dir}/s' --threads 0", 2, {"--threads"}},
        Invocation{"a_million_threads",
                   "study '{src}/studies/accuracy/study.json' --out '{dir}/s' --threads 1000000",
                   2,
                   {"--threads"}},
        Invocation{
            "a_million_segments",
            "identify '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /bodies/0/mass --segments 1000000",
            2,
            {"--segments"}},
        Invocation{"a_million_samples", "tune '{dir}/pendulum.json' --samples 1000000", 2, {"--samples"}},
        // no lost or corrupted file
        Invocation{
            "output_onto_the_input", "simulate '{dir}/pendulum.json' -o '{dir}/pendulum.json'", 2, {"-o", "input"}},
        Invocation{"written_scene_onto_the_input",
                   "tune '{dir}/pendulum.json' --write-scene '{dir}/pendulum.json'",
                   2,
                   {"--write-scene", "input"}},
        Invocation{"output_into_a_missing_folder",
                   "simulate '{dir}/pendulum.json' -o '{dir}/no/such/out.csv'",
                   2,
                   {"-o", "folder"}},
        Invocation{
            "a_plot_that_is_neither_png_nor_svg",
            "identify '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /bodies/0/mass --plot '{dir}/fit.pdf'",
            2,
            {"--plot", ".png or .svg"}},
        Invocation{"a_full_disk_on_stdout",
                   "simulate '{dir}/pendulum.json'",
                   1,
                   {"standard output"},
                   "sh -c '\"$0\" \"$@\" >/dev/full' "},
        Invocation{"a_full_disk_on_the_output", "simulate '{dir}/pendulum.json' -o /dev/full", 1, {"/dev/full"}},
        Invocation{"output_onto_a_device", "simulate '{dir}/pendulum.json' -o /dev/null", 0, {}},
        Invocation{"a_duplicate_key",
                   "simulate '{dir}/duplicate_key.json'",
                   2,
                   {"duplicate_key.json", "/bodies/0/mass", "duplicate"}},
        // issue 34: inputs that are not files, data with nothing to fit, numbers outside their domain by a flag,
        // flags a command would have ignored, XML nested past any parser's stack
        Invocation{"a_folder_as_the_scene", "simulate '{dir}'", 2, {"is a folder, not a file"}},
        Invocation{"a_device_as_the_scene", "check /dev/zero", 2, {"/dev/zero", "not a regular file"}},
        Invocation{"a_device_as_the_data",
                   "identify '{dir}/pendulum.json' --data /dev/zero --param /bodies/0/mass",
                   2,
                   {"/dev/zero", "data file", "not a regular file"}},
        Invocation{"a_device_as_the_model",
                   "import '{dir}/zero.urdf' -o '{dir}/out.json'",
                   2,
                   {"zero.urdf", "not a regular file"}},
        Invocation{"a_device_as_the_study", "study /dev/zero --out '{dir}/s'", 2, {"/dev/zero", "not a regular file"}},
        Invocation{"data_without_a_value",
                   "fit '{dir}/pendulum.json' --data '{dir}/empty_cells.csv' --param /bodies/0/mass",
                   2,
                   {"empty_cells.csv", "no observed value"}},
        Invocation{"a_tie_to_a_negative_mass",
                   "gradient '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /constraints/0/length --tie "
                   "'/bodies/0/mass=-1'",
                   2,
                   {"--tie", "/bodies/0/mass", "must be > 0"}},
        Invocation{"a_parameter_with_an_empty_index",
                   "gradient '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /bodies//mass",
                   2,
                   {"/bodies//mass", "is not in the scene file"}},
        Invocation{
            "a_parameter_with_a_huge_index",
            "gradient '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /bodies/99999999999999999999/mass",
            2,
            {"/bodies/99999999999999999999/mass", "is not in the scene file"}},
        Invocation{"segments_far_beyond_the_data",
                   "identify '{dir}/pendulum.json' --data '{dir}/on_time.csv' --param /bodies/0/mass --segments 1000",
                   2,
                   {"--segments 1000", "3 rows of data"}},
        Invocation{"a_hub_held_by_2049_rows",  // MuJoCo's softbox has 1090; 3000 ran out of memory
                   "simulate '{dir}/hub.json' -o '{dir}/out.csv'",
                   2,
                   {"hub.json", "/bodies/0", "2049 constraint rows act on body 'hub'", "2048"}},
        Invocation{"check_on_a_hub_held_by_2049_rows", "check '{dir}/hub.json'", 2, {"hub.json", "/bodies/0"}},
        Invocation{"a_misspelled_command",
                   "simulat '{dir}/pendulum.json'",
                   2,
                   {"unknown command 'simulat'", "did you mean 'simulate'?"}},
        Invocation{"misspelled_flags_in_order_with_the_nearest",  // CLI11 listed them last first, unnamed
                   "simulate '{dir}/pendulum.json' --stpe 0.1 --durtion 2 extra",
                   2,
                   {"simulate: unknown flag '--stpe' (did you mean '--step'?); unknown flag '--durtion' (did you "
                    "mean '--duration'?); unexpected argument 'extra'"}},
        Invocation{"a_misspelled_flag_before_the_required_one_it_left_out",
                   "identify '{dir}/pendulum.json' --data '{dir}/on_time.csv' --parm /bodies/0/mass",
                   2,
                   {"unknown flag '--parm' (did you mean '--param'?)\ntether: --param is required"}},
        Invocation{"a_study_out_that_is_a_file",  // "cannot make the folder"
                   "study '{dir}/small_study.json' --out '{dir}/pendulum.json'",
                   2,
                   {"--out", "pendulum.json' is a file, not a folder"}},
        Invocation{"an_mjcf_name_that_is_not_utf8",  // the importer fuzzer's: JSON's exception ended the process
                   "import '{src}/fuzz/corpus/findings/mjcf/name_not_utf8.xml' -o '{dir}/out.json'",
                   2,
                   {"name_not_utf8.xml", "not valid UTF-8"}},
        Invocation{
            "a_urdf_prismatic_joint_at_its_stop_by_rounding",  // refused: 1.7e-16 m outside its range
            "import '{src}/fuzz/corpus/findings/urdf/prismatic_at_its_stop_by_rounding.urdf' -o '{dir}/out.json'",
            0,
            {}},
        Invocation{"tune_with_a_gain_it_chooses", "tune '{dir}/pendulum.json' --alpha 5", 2, {"--alpha"}},
        Invocation{"xml_nested_100000_deep",
                   "import '{dir}/nested.urdf' -o '{dir}/out.json'",
                   2,
                   {"nested.urdf", "nested deeper than 500"}},
        Invocation{"version", "--version", 0, {}}),
    [](const ::testing::TestParamInfo<Invocation>& info) { return std::string(info.param.name); });

class ReliabilityFiles : public ::testing::Test {
 protected:
  Outcome Tether(const std::string& args) const { return testing::RunTether(args, folder_); }
  std::string Path(const std::string& name) const { return folder_.Path(name); }
  TempFolder folder_{"tether_reliability_files"};
};

TEST_F(ReliabilityFiles, AGradientRowWithinRoundingOfTheEndIsServedByTheEnd) {
  const std::string scene = folder_.Write("pendulum.json", kPendulum);
  folder_.Write("late.csv", "t,bob.x\n0,0.6\n0.5,0.1\n1.000000000000005,0.3\n");
  folder_.Write("on_time.csv", "t,bob.x\n0,0.6\n0.5,0.1\n1,0.3\n");
  const Outcome late = Tether("gradient '" + scene + "' --data '" + Path("late.csv") + "' --param /bodies/0/mass");
  const Outcome on_time = Tether("gradient '" + scene + "' --data '" + Path("on_time.csv") + "' --param /bodies/0/mass");
  ASSERT_EQ(late.status, 0) << late.err;
  ASSERT_EQ(on_time.status, 0) << on_time.err;
  const double loss = nlohmann::json::parse(late.out)["loss"].get<double>();
  EXPECT_TRUE(std::isfinite(loss));
  EXPECT_EQ(loss, nlohmann::json::parse(on_time.out)["loss"].get<double>());
}

TEST_F(ReliabilityFiles, ADataFileOverOneGibibyteIsRefusedBeforeReading) {
  const std::string scene = folder_.Write("pendulum.json", kPendulum);
  const std::string data = Path("huge.csv");
  ASSERT_EQ(::truncate(folder_.Write("huge.csv", "t,bob.x\n").c_str(), (1ll << 30) + 1), 0);  // sparse: no disk
  const Outcome run = Tether("gradient '" + scene + "' --data '" + data + "' --param /bodies/0/mass");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "huge.csv")) << run.err;
  EXPECT_TRUE(Contains(run.err, "more than tether reads")) << run.err;
}

TEST_F(ReliabilityFiles, EveryNloptAlgorithmRunsOrIsRefusedNamingTheFlag) {
  const std::string scene = folder_.Write("pendulum.json", kPendulum);
  for (const char* name :
       {"GN_DIRECT", "GN_DIRECT_L", "GN_DIRECT_L_RAND", "GN_DIRECT_NOSCAL", "GN_DIRECT_L_NOSCAL",
        "GN_DIRECT_L_RAND_NOSCAL", "GN_ORIG_DIRECT", "GN_ORIG_DIRECT_L", "GD_STOGO", "GD_STOGO_RAND",
        "LD_LBFGS_NOCEDAL", "LD_LBFGS", "LN_PRAXIS", "LD_VAR1", "LD_VAR2", "LD_TNEWTON", "LD_TNEWTON_RESTART",
        "LD_TNEWTON_PRECOND", "LD_TNEWTON_PRECOND_RESTART", "GN_CRS2_LM", "GN_MLSL", "GD_MLSL", "GN_MLSL_LDS",
        "GD_MLSL_LDS", "LD_MMA", "LN_COBYLA", "LN_NEWUOA", "LN_NEWUOA_BOUND", "LN_NELDERMEAD", "LN_SBPLX",
        "LN_AUGLAG", "LD_AUGLAG", "LN_AUGLAG_EQ", "LD_AUGLAG_EQ", "LN_BOBYQA", "GN_ISRES", "AUGLAG", "AUGLAG_EQ",
        "G_MLSL", "G_MLSL_LDS", "LD_SLSQP", "LD_CCSAQ", "GN_ESCH", "GN_AGS"}) {
    const Outcome run = Tether("tune '" + scene + "' --duration 0.2 --max-evaluations 12 --optimizer nlopt:" + name);
    EXPECT_TRUE(run.status == 0 || (run.status == 2 && Contains(run.err, "--optimizer"))) << name << ": " << run.status
                                                                                          << "\n" << run.err;
  }
}

TEST_F(ReliabilityFiles, OutputThroughASymbolicLinkReplacesItsTargetAndKeepsTheLink) {
  const std::string scene = folder_.Write("pendulum.json", kPendulum);
  const std::string target = folder_.Write("target.csv", "old\n");
  std::filesystem::create_symlink(target, Path("link.csv"));
  const Outcome run = Tether("simulate '" + scene + "' --duration 0.01 -o '" + Path("link.csv") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(std::filesystem::is_symlink(Path("link.csv")));
  EXPECT_TRUE(Contains(ReadText(target), "t,bob.x"));
  // a link onto the input is the input
  std::filesystem::create_symlink(scene, Path("scene_link.json"));
  EXPECT_EQ(Tether("simulate '" + scene + "' -o '" + Path("scene_link.json") + "'").status, 2);
}

TEST_F(ReliabilityFiles, CheckOnATenThousandParticleChainTakesTheSparsePath) {
  nlohmann::json bodies = nlohmann::json::array(), constraints = nlohmann::json::array();
  for (int k = 0; k < 10000; ++k) {
    const std::string name = "p" + std::to_string(k);
    bodies.push_back({{"name", name}, {"type", "particle"}, {"mass", 1e-4}, {"position", {2e-4 * (k + 1), 0.0}}});
    constraints.push_back({{"type", "distance"}, {"bodies", {k ? "p" + std::to_string(k - 1) : "world", name}},
                           {"length", 2e-4}});
  }
  const std::string scene = folder_.Write("chain.json", nlohmann::json{{"dimension", 2}, {"bodies", bodies},
                                                                       {"constraints", constraints}}.dump());
  const Outcome run = Tether("check '" + scene + "'");  // the dense SVD needed 4.8 GB and 30 s
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(Contains(run.out, "10000 constraint rows of rank 10000: 10000 degrees of freedom")) << run.out;
  EXPECT_TRUE(Contains(run.out, "estimated")) << run.out;
}

// Sends `signal` to a tether run once `file` has at least `lines` lines (at most 60 s after it starts), and
// returns the run's outcome (status 128 + signal when the signal ended it). Waiting for the file, not for a
// time, keeps the test independent of the machine's speed (the sanitizer build runs several times slower).
Outcome Interrupted(const std::string& args, int signal, const std::string& file, int lines, const TempFolder& folder) {
  std::ostringstream launcher;
  // `file` unquoted, so that a pattern (a temporary file's NAME.partial.*) matches; the test folders have no spaces
  launcher << "sh -c '\"$0\" \"$@\" & pid=$!; n=0; while [ $n -lt 1200 ] && [ \"$(cat " << file
           << " 2>/dev/null | wc -l)\" -lt " << lines << " ]; do sleep 0.05; n=$((n + 1)); done; kill -" << signal
           << " $pid; wait $pid' ";
  return testing::RunTether(args, folder, launcher.str());
}

TEST_F(ReliabilityFiles, AnInterruptedRunLeavesNoTemporaryFileAndNoOutput) {
  const std::string scene = folder_.Write("pendulum.json", kPendulum);
  for (int signal : {2, 15}) {  // SIGINT, SIGTERM
    // once the temporary file holds 1000 lines of CSV the run is well under way
    const Outcome run = Interrupted("simulate '" + scene + "' --duration 20000 -o '" + Path("out.csv") + "'", signal,
                                    Path("out.csv") + ".partial.*", 1000, folder_);
    EXPECT_EQ(run.status, 128 + signal) << run.err;
    for (const std::string& name : folder_.Entries()) EXPECT_FALSE(Contains(name, "out.csv")) << name;
  }
}

// Ctrl-C reaches the whole foreground group: while a study draws, python and tether (waiting with SIGINT ignored)
// both get it. The drawing was reported as a failed one ("python3 with matplotlib is needed").
TEST_F(ReliabilityFiles, CtrlCWhileAStudyDrawsEndsItAsCtrlCWithItsResultsComplete) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/step": [0.01, 0.005]}, "metrics": ["max_constraint_error"]})");
  const std::string out = Path("drawn");
  const std::string python = "tether-plot-[^ ]*/script[.]py .*" + out;  // this test's drawing, not another's
  std::ostringstream launcher;
  launcher << "sh -c '\"$0\" \"$@\" & pid=$!; n=0; while [ $n -lt 1200 ] && ! pgrep -f \"" << python
           << "\" >/dev/null; do sleep 0.02; n=$((n + 1)); done; kill -2 $pid; pkill -2 -f \"" << python
           << "\"; wait $pid' ";
  const Outcome run = testing::RunTether("study '" + study + "' --out '" + out + "' --quiet", folder_, launcher.str());
  EXPECT_EQ(run.status, 130) << run.err;
  EXPECT_TRUE(Contains(run.err, "interrupted while drawing the figures")) << run.err;
  EXPECT_FALSE(Contains(run.err, "matplotlib is needed")) << run.err;
  EXPECT_EQ(testing::Lines(ReadText(out + "/results.csv")).size(), 3u);  // written before the figures
  EXPECT_TRUE(std::filesystem::exists(out + "/summary.md"));
}

// A process limit on threads (ulimit -u) that lets the first threads start and refuses the next: a study on two
// threads and a fit's parallel starts left a started thread joinable behind the exception, and the process aborted.
// The work now runs on the threads that started, or on the calling one.
TEST_F(ReliabilityFiles, AThreadLimitRunsTheWorkOnTheThreadsThatStarted) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/step": [0.01, 0.005, 0.002, 0.001]}, "metrics": ["max_constraint_error"]})");
  for (const char* allowed : {"0", "1"}) {
    const std::string launcher =
        std::string("env LD_PRELOAD=") + TETHER_THREAD_LIMIT_PRELOAD + " TETHER_THREADS_ALLOWED=" + allowed + " ";
    const std::string out = Path(std::string("out") + allowed);
    const Outcome run =
        testing::RunTether("study '" + study + "' --out '" + out + "' --threads 2 --quiet", folder_, launcher);
    EXPECT_EQ(run.status, 0) << allowed << " threads allowed\n" << run.err;
    EXPECT_EQ(testing::Lines(ReadText(out + "/results.csv")).size(), 5u) << run.err;
    const Outcome fit = testing::RunTether(
        "fit '" + kSource +
            "/docs/examples/swing_up/pendulum.json' --param '/effects/1/schedule/values/*' "
            "--bound '/effects/1/schedule/values/*=-2:2' --at-least axle.angle=3@3 --starts 3 --max-evaluations 20",
        folder_, launcher);
    EXPECT_TRUE(fit.status == 0 || fit.status == 1) << allowed << " threads allowed: status " << fit.status << "\n"
                                                    << fit.err;  // a finished fit, met or not; never an abort
    EXPECT_TRUE(Contains(fit.out, "\"parameters\"")) << fit.out;
  }
}

TEST_F(ReliabilityFiles, CtrlCDuringAStudyIsReportedAndTheStudyResumes) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/duration": [300, 301, 302, 303, 304, 305, 306, 307, 308, 309, 310, 311, 312, 313, 314, 315,
                                        316, 317, 318, 319, 320, 321, 322, 323]},
    "metrics": ["max_constraint_error"]})");
  const std::string out = Path("out");
  // interrupted once the first row is in the partial results (a row takes 0.15 s or more: 300 s of a pendulum
  // at 1 ms), so that some rows are done and most are not
  const Outcome stopped =
      Interrupted("study '" + study + "' --out '" + out + "' --threads 1", 2, out + "/results.partial.csv", 3, folder_);
  ASSERT_EQ(stopped.status, 130) << stopped.err;
  EXPECT_TRUE(Contains(stopped.err, "interrupted")) << stopped.err;
  EXPECT_TRUE(Contains(stopped.err, "resumes")) << stopped.err;
  ASSERT_TRUE(std::filesystem::exists(out + "/results.partial.csv"));
  const size_t finished = testing::Lines(ReadText(out + "/results.partial.csv")).size() - 2;
  EXPECT_GT(finished, 0u);
  EXPECT_LT(finished, 24u);
  // with its scene changed since, the partial results are another study's: refused, naming --out and --restart
  const std::string original = ReadText(Path("pendulum.json"));
  folder_.Write("pendulum.json", std::string(original).replace(original.find("\"mass\": 1.0"), 11, "\"mass\": 2.0"));
  const Outcome changed = Tether("study '" + study + "' --out '" + out + "' --threads 1 --quiet");
  EXPECT_EQ(changed.status, 2) << changed.err;
  EXPECT_TRUE(Contains(changed.err, "--restart")) << changed.err;
  EXPECT_EQ(testing::Lines(ReadText(out + "/results.partial.csv")).size() - 2, finished);  // kept as it was
  folder_.Write("pendulum.json", original);
  // as it was, it resumes and completes
  const Outcome resumed = Tether("study '" + study + "' --out '" + out + "' --threads 1 --quiet");
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_EQ(testing::Lines(ReadText(out + "/results.csv")).size(), 25u);
  EXPECT_FALSE(std::filesystem::exists(out + "/results.partial.csv"));
  EXPECT_EQ(resumed.err.find("runs, about"), std::string::npos) << resumed.err;  // --quiet
}

TEST_F(ReliabilityFiles, TwoStudiesIntoOneFolderDoNotInterleave) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/simulation/duration": [400, 401, 402, 403]}, "metrics": ["seconds"]})");
  const std::string out = Path("out");
  // the second starts once the first holds the folder (its partial results exist)
  const std::string both = "sh -c '\"$0\" \"$@\" & n=0; while [ $n -lt 1200 ] && [ ! -f \"" + out +
                           "/results.partial.csv\" ]; do sleep 0.05; n=$((n + 1)); done; \"$0\" \"$@\"; "
                           "echo second=$? >&2; wait' ";
  const Outcome run = testing::RunTether("study '" + study + "' --out '" + out + "' --threads 1 --quiet", folder_, both);
  EXPECT_TRUE(Contains(run.err, "another tether study is writing")) << run.err;
  EXPECT_TRUE(Contains(run.err, "second=2")) << run.err;
  EXPECT_EQ(testing::Lines(ReadText(out + "/results.csv")).size(), 5u);
}

TEST_F(ReliabilityFiles, ASweptArrayIsOneQuotedCellOfTheResults) {
  folder_.Write("pendulum.json", kPendulum);
  const std::string study = folder_.Write("study.json", R"({"scene": "pendulum.json",
    "sweep": {"/bodies/0/position": [[0.6, -0.35], [0.35, -0.6]]}, "metrics": ["max_constraint_error"]})");
  const Outcome run = Tether("study '" + study + "' --out '" + Path("out") + "' --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> lines = testing::Lines(ReadText(Path("out/results.csv")));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[1].rfind("\"[0.6,-0.35]\",", 0), 0u) << lines[1];
  EXPECT_EQ(testing::CsvCells(lines[1]).size(), 3u) << lines[1];
}

// Valid scenes far off their constraints assemble: a cart on a slider and a bob on a rod from it, started
// anywhere within a few rod lengths, with masses up to a millionfold apart and lengths from 1 mm to 100 m (the
// nearest-state iteration alone failed on 124 of 300 such scenes).
TEST(ReliabilityAssembly, CartsAndBobsFarOffTheirConstraintsAssemble) {
  std::mt19937 random(15);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double lengths[] = {1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0}, offsets[] = {0.0, 1.0, 100.0, 1e4},
               masses[] = {1e-3, 1.0, 1e3};
  for (int trial = 0; trial < 200; ++trial) {
    const double length = lengths[random() % 6], offset = offsets[random() % 4];
    const double cart_x = offset + unit(random) * length, cart_y = offset + unit(random) * length;
    const nlohmann::json scene = {
        {"dimension", 2},
        {"bodies", {{{"name", "cart"}, {"type", "particle"}, {"mass", masses[random() % 3]}, {"position", {cart_x, cart_y}}},
                    {{"name", "bob"}, {"type", "particle"}, {"mass", masses[random() % 3]},
                     {"position", {cart_x + 2 * unit(random) * length, cart_y + 2 * unit(random) * length}}}}},
        {"constraints", {{{"type", "slider"}, {"bodies", {"world", "cart"}}, {"points", {{offset, offset}, {0.0, 0.0}}},
                          {"axis", {unit(random), unit(random)}}},
                         {{"type", "distance"}, {"bodies", {"cart", "bob"}}, {"length", length}}}}};
    const Model<double> model = ParseScene(scene, "cart.json").model;
    RunReport report;
    try {
      const State<double> start = AssembledInitialState(model, &report);
      EXPECT_NEAR((start.q.segment<2>(2) - start.q.segment<2>(0)).norm(), length, 1e-9 * (length + offset))
          << scene.dump();
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what() << "\n" << scene.dump();
    }
  }
}

}  // namespace
}  // namespace tether
