// `tether import` through the command line: the scene it writes (to -o or stdout) is one `tether simulate` runs
// as it is, warnings go to stderr, and bad input exits 2 with a message naming the file or the flag and writes
// nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_files.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether::testing {
namespace {

const std::string kArm = std::string(TETHER_SOURCE_DIR) + "/docs/examples/urdf_arm/arm.urdf";

TEST(ImportCli, WritesASceneThatSimulatesAsItIs) {
  const TempFolder folder;
  const Outcome imported = RunTether("import " + kArm + " --joint elbow=0.4 --joint-velocity shoulder_yaw=1 -o " +
                                         folder.Path("arm.json"),
                                     folder);
  ASSERT_EQ(imported.status, 0) << imported.err;
  EXPECT_EQ(imported.out, "");
  EXPECT_EQ(imported.err.find("joint limits"), std::string::npos);  // kept, and enforced: nothing to warn about
  const Scene scene = ReadSceneFile(folder.Path("arm.json"));
  EXPECT_TRUE(HasJointLimits(scene.model));
  EXPECT_EQ(scene.model.bodies.size(), 6u);
  const Outcome run = RunTether("simulate " + folder.Path("arm.json") + " --duration 0.1 -o " + folder.Path("arm.csv"), folder);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");  // on its constraints from the start: nothing to assemble
  const std::vector<std::string> rows = Lines(ReadText(folder.Path("arm.csv")));
  const std::vector<std::string> header = CsvCells(rows[0]), first = CsvCells(rows[1]);
  for (size_t k = 0; k < header.size(); ++k) {
    if (header[k] == "elbow.angle") EXPECT_NEAR(std::stod(first[k]), 0.4, 1e-12);
    if (header[k] == "shoulder_yaw.omega") EXPECT_NEAR(std::stod(first[k]), 1.0, 1e-12);
  }
  // without -o the scene goes to stdout, the same
  const Outcome printed = RunTether("import " + kArm + " --joint elbow=0.4 --joint-velocity shoulder_yaw=1", folder);
  EXPECT_EQ(printed.status, 0);
  EXPECT_EQ(printed.out, ReadText(folder.Path("arm.json")));
}

TEST(ImportCli, BadInputExitsTwoNamingTheFileOrFlagAndWritesNothing) {
  const TempFolder folder;
  const std::string out = folder.Path("out.json");
  const std::string bad_urdf = folder.Write("bad.urdf", "<robot name=\"r\"><link name=\"a\"/>");
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"import " + folder.Path("none.urdf") + " -o " + out,
       folder.Path("none.urdf") + ": cannot open the model file (no such file)"},
      {"import " + folder.Write("model.sdf", "") + " -o " + out, "model.sdf: unknown model format"},
      {"import " + bad_urdf + " -o " + out, "bad.urdf: not a valid URDF model"},
      {"import " + kArm + " --joint elbow -o " + out, "--joint elbow: expected NAME=VALUE with a finite number"},
      {"import " + kArm + " --joint elbow=x -o " + out, "--joint elbow=x: expected NAME=VALUE with a finite number"},
      {"import " + kArm + " --joint-velocity =1 -o " + out, "--joint-velocity =1: expected NAME=VALUE"},
      {"import " + kArm + " --joint knee=1 -o " + out, "--joint knee: the model has no joint named 'knee'"},
      {"import " + kArm + " --joint shoulder_pitch=2.5 -o " + out,
       "--joint shoulder_pitch=2.5: outside the joint's range [-2, 2]"},
      {"import " + kArm + " --fix tool0 -o " + out, "--fix tool0: no moving body of " + kArm + " is named 'tool0'"},
      {"import " + kArm + " --fix wrist -o " + out, "--fix wrist: the link 'wrist' of " + kArm + " has no mass"},
      {"import " + kArm + " -o " + kArm, "-o"},
      {"import " + kArm + " -o " + folder.Path("missing/out.json"), "-o"},
      // a NaN in the model: refused, where it was dropped (gravity) and MuJoCo's warning about it went to stdout
      // and to MUJOCO_LOG.TXT in the working folder
      {"import " +
           folder.Write("nan_gravity.xml",
                        "<mujoco><option gravity=\"nan 0 -9.81\"/><worldbody>"
                        "<body name=\"b\" pos=\"0 0 1\"><joint type=\"hinge\"/>"
                        "<geom size=\"0.1\"/></body></worldbody></mujoco>") +
           " -o " + out,
       "nan_gravity.xml: the model's gravity is not finite"},
      // a massless moving link: its mass named, not principal moments of "nan, nan, -nan"
      {"import " +
           folder.Write("massless.urdf",
                        "<robot name=\"r\"><link name=\"base\"/><link name=\"a\"><inertial>"
                        "<mass value=\"0\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" "
                        "ixz=\"0\" iyz=\"0\"/></inertial></link><joint name=\"j\" "
                        "type=\"continuous\"><parent link=\"base\"/><child link=\"a\"/>"
                        "<axis xyz=\"0 0 1\"/></joint></robot>") +
           " -o " + out,
       "link 'a': its mass is 0 kg"}};
  std::filesystem::remove("MUJOCO_LOG.TXT");  // the tests run where tether runs: a log left here is its
  for (const Case& c : cases) {
    const Outcome outcome = RunTether(c.args, folder);
    EXPECT_EQ(outcome.status, 2) << c.args << "\n" << outcome.err;
    EXPECT_NE(outcome.err.find("tether: error: "), std::string::npos) << outcome.err;
    EXPECT_NE(outcome.err.find(c.message), std::string::npos) << outcome.err;
    EXPECT_EQ(outcome.out, "");
    EXPECT_FALSE(std::ifstream(out).good()) << c.args;
  }
  EXPECT_NE(ReadText(kArm).find("<robot name=\"test_arm\">"), std::string::npos);  // -o onto it was refused
  EXPECT_FALSE(std::filesystem::exists("MUJOCO_LOG.TXT")) << "MuJoCo wrote its log into the working folder";
}

}  // namespace
}  // namespace tether::testing
