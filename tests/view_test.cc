// tether view (viewer/include/tether/viewer/view.h, docs/view.md): the glyphs are the uniform solids of the bodies'
// mass and inertia, the frames keep at most 60 a second and always the last, the page carries everything it needs
// (no file or address is fetched when it opens), and the command refuses bad input with status 2 and no file. The
// browser tests (python/tests/test_view_browser.py) open the pages in headless Chromium.
#include "tether/viewer/view.h"

#include <gtest/gtest.h>

#include <string>

#include "test_files.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {
namespace {

using nlohmann::json;

Model<double> Parse(const json& scene) { return ParseScene(scene, "view.json").model; }

TEST(View, GlyphsAreTheUniformSolidsOfTheBodiesMassAndInertia) {
  // a 2 kg box 0.1 x 0.2 x 0.3 (principal moments m (b^2 + c^2) / 12, ...), a particle, a planar plate
  const double m = 2.0, a = 0.1, b = 0.2, c = 0.3;
  const json scene = {{"dimension", 3},
                      {"bodies",
                       {{{"name", "box"},
                         {"type", "rigid"},
                         {"mass", m},
                         {"position", {0, 0, 0}},
                         {"inertia", {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12}}},
                        {{"name", "bead"}, {"type", "particle"}, {"mass", 1.0}, {"position", {1, 0, 0}}}}}};
  const json drawing = ViewDrawing(Parse(scene));
  ASSERT_EQ(drawing["bodies"].size(), 2u);
  const json& box = drawing["bodies"][0]["glyph"];
  EXPECT_EQ(box["type"], "box");
  const double edges[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(box["size"][k].get<double>(), edges[k], 1e-12) << k;
  EXPECT_EQ(drawing["bodies"][1]["glyph"]["type"], "sphere");
  EXPECT_NEAR(drawing["bodies"][1]["glyph"]["radius"].get<double>(), drawing["scale"].get<double>() / 20, 1e-15);
  const json planar = {{"dimension", 2},
                       {"bodies",
                        {{{"name", "plate"},
                          {"type", "rigid"},
                          {"mass", m},
                          {"inertia", m * (a * a + a * a) / 12},
                          {"position", {0, 0}},
                          {"angle", 0.0}}}}};
  EXPECT_NEAR(ViewDrawing(Parse(planar))["bodies"][0]["glyph"]["size"][0].get<double>(), a, 1e-12);
}

TEST(View, ABodyWithShapesIsDrawnFromThemAndJointsAndMarkersFromTheScene) {
  const json scene = {
      {"dimension", 3},
      {"bodies", {{{"name", "ball"}, {"type", "particle"}, {"mass", 1.0}, {"position", {0, 0, -1}}}}},
      {"constraints", {{{"type", "distance"}, {"name", "rod"}, {"bodies", {"world", "ball"}}, {"length", 1.0}}}},
      {"markers", {{{"name", "tip"}, {"body", "ball"}, {"point", {0, 0, 0}}}}},
      {"shapes", {{{"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}}}}};
  const json drawing = ViewDrawing(Parse(scene));
  EXPECT_FALSE(drawing["bodies"][0].contains("glyph"));
  EXPECT_EQ(drawing["shapes"][0]["type"], "sphere");
  EXPECT_EQ(drawing["joints"][0]["type"], "distance");
  EXPECT_EQ(drawing["markers"][0]["name"], "tip");
}

json Pendulum(double duration) {
  return {{"dimension", 2},
          {"bodies", {{{"name", "bob"}, {"type", "particle"}, {"mass", 1.0}, {"position", {1.0, 0.0}}}}},
          {"constraints", {{{"type", "distance"}, {"bodies", {"world", "bob"}}, {"length", 1.0}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}}}},
          {"simulation", {{"step", 1e-3}, {"duration", duration}}}};
}

TEST(View, FramesAreAtMostSixtyASecondAndTheLastStateIsOne) {
  const ViewFrames frames = SimulatedFrames(Parse(Pendulum(1.005)));
  ASSERT_GE(frames.times.size(), 61u);
  EXPECT_EQ(frames.times.front(), 0.0);
  EXPECT_NEAR(frames.times.back(), 1.005, 1e-12);
  for (size_t k = 1; k + 1 < frames.times.size(); ++k) {
    EXPECT_GE(frames.times[k], (k - 1e-9) / kViewFramesPerSecond) << k;
    EXPECT_LT(frames.times[k] - frames.times[k - 1], 1.0 / kViewFramesPerSecond + 1e-3) << k;
  }
  EXPECT_EQ(frames.poses.back().size(), 7u);
  ASSERT_EQ(frames.series_names, (std::vector<std::string>{"constraint_error", "energy"}));
  ASSERT_EQ(frames.series.size(), frames.times.size());
  EXPECT_NEAR(frames.series.back()[1], frames.series.front()[1], 1e-6);  // rk4 keeps the pendulum's energy
  EXPECT_NEAR(std::hypot(frames.poses.back()[0], frames.poses.back()[1]), 1.0, 1e-6);  // on its circle
}

TEST(View, ThePageCarriesEverythingItDraws) {
  const std::string page = ViewHtml(Parse(Pendulum(0.5)), "a <title>", SimulatedFrames(Parse(Pendulum(0.5))));
  EXPECT_NE(page.find("<title>a &lt;title&gt;</title>"), std::string::npos);
  std::string markup = page;  // the page without its scripts' text: nothing in it names a file or an address
  for (size_t open = markup.find("<script"); open != std::string::npos; open = markup.find("<script", open + 1)) {
    const size_t close = markup.find("</script>", open);
    ASSERT_NE(close, std::string::npos);
    markup.erase(markup.find('>', open) + 1, close - markup.find('>', open) - 1);
  }
  for (const char* fetch : {"src=", "href=", "url(", "@import"})
    EXPECT_EQ(markup.find(fetch), std::string::npos) << fetch;
  EXPECT_LT(markup.size(), 4000u);
  EXPECT_NE(page.find("REVISION=\"111\""), std::string::npos);  // Debian's three.js r111, inlined
  EXPECT_NE(page.find("OrbitControls"), std::string::npos);
}

TEST(ViewCli, BadInputIsRefusedWithStatus2AndNoFile) {
  const testing::TempFolder folder;
  const std::string scene = folder.Write("pendulum.json", Pendulum(0.5).dump());
  const std::string page = folder.Path("view.html");
  const struct {
    std::string args, message;
  } cases[] = {
      {"view " + scene, "-o"},
      {"view " + scene + " -o " + page + " --data " + folder.Write("empty.csv", ""),
       "empty.csv: the data file is empty"},
      {"view " + scene + " -o " + page + " --data " + folder.Write("no_pose.csv", "t,energy\n0,1\n"),
       "no_pose.csv: no column for body 'bob'"},
      {"view " + scene + " -o " + page + " --data " + folder.Write("gap.csv", "t,bob.x,bob.y\n0,1,0\n0.1,,0\n"),
       "gap.csv: line 3: the cell of column bob.x is empty"},
      {"view " + scene + " -o " + scene, "-o"},
      {"view " + scene + " -o " + page + " --compare " + scene, "--compare: draws a simulation beside the recording"},
      {"view " + scene + " -o " + page + " --duration 1e6", "the page would hold 60000002 frames of 1 bodies"},
  };
  for (const auto& c : cases) {
    const testing::Outcome outcome = testing::RunTether(c.args, folder);
    EXPECT_EQ(outcome.status, 2) << c.args << "\n" << outcome.err;
    EXPECT_NE(outcome.err.find(c.message), std::string::npos) << outcome.err;
  }
  for (const std::string& entry : folder.Entries()) EXPECT_NE(entry, "view.html");
  EXPECT_EQ(testing::RunTether("view " + scene + " -o " + page, folder).status, 0);
  // a run's warnings are said as tether simulate says them
  json drifting = Pendulum(2.0);  // explicit Euler at 10 ms without stabilization: past 1% of its length by 0.33 s
  drifting["simulation"] = {{"integrator", "euler"}, {"step", 0.01}, {"duration", 2.0}};
  drifting["stabilization"] = {{"method", "none"}};
  const std::string drift = folder.Write("drift.json", drifting.dump());
  const testing::Outcome simulated = testing::RunTether("simulate " + drift + " -o " + folder.Path("d.csv"), folder);
  const testing::Outcome viewed = testing::RunTether("view " + drift + " -o " + folder.Path("d.html"), folder);
  EXPECT_EQ(viewed.status, 0) << viewed.err;
  EXPECT_NE(simulated.err.find("warning: " + drift + ": t = 0.33: the constraints have drifted"), std::string::npos)
      << simulated.err;
  EXPECT_EQ(viewed.err, simulated.err);
  EXPECT_NE(testing::ReadText(page).find("tether-data"), std::string::npos);
}

}  // namespace
}  // namespace tether
