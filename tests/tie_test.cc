// Tied parameters (`--tie PTR=EXPR`, autodiff/tie_expression.h, ParameterSet::Tie): the expression's grammar
// and errors, gradients through a tie against central differences of the tied loss (Jets and the adjoint), an
// identification with a rod's inertia tied to its mass, a knot list following another element by element, and
// the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/autodiff/residuals.h"
#include "tether/autodiff/tie_expression.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/identify.h"

namespace tether {
namespace {

using json = nlohmann::json;

double Evaluate(const std::string& text, const std::vector<double>& values = {}) {
  return TieExpression(text, "--tie").Evaluate(values);
}

TEST(TieExpression, FollowsTheUsualPrecedenceWithARightAssociativePower) {
  EXPECT_DOUBLE_EQ(Evaluate("1 + 2 * 3"), 7.0);
  EXPECT_DOUBLE_EQ(Evaluate("(1 + 2) * 3"), 9.0);
  EXPECT_DOUBLE_EQ(Evaluate("2 ^ 3 ^ 2"), 512.0);
  EXPECT_DOUBLE_EQ(Evaluate("-2 ^ 2"), -4.0);
  EXPECT_DOUBLE_EQ(Evaluate("2 ^ -1"), 0.5);
  EXPECT_DOUBLE_EQ(Evaluate("8 / 4 / 2"), 1.0);
  EXPECT_DOUBLE_EQ(Evaluate("1 - 2 - 3"), -4.0);
  EXPECT_DOUBLE_EQ(Evaluate("1.5e-1 * 2"), 0.3);
  const TieExpression e("{/bodies/1/mass} * {/x}^2 / 12 + {/bodies/1/mass}", "--tie");
  EXPECT_EQ(e.references(), (std::vector<std::string>{"/bodies/1/mass", "/x"}));
  EXPECT_DOUBLE_EQ(e.Evaluate(std::vector<double>{0.7, 0.6}), 0.7 * 0.36 / 12 + 0.7);
}

TEST(TieExpression, NestsDeeplyButNotWithoutBound) {
  EXPECT_DOUBLE_EQ(Evaluate(std::string(100, '(') + "1" + std::string(100, ')')), 1.0);
  EXPECT_DOUBLE_EQ(Evaluate(std::string(100, '-') + "1"), 1.0);
  for (const std::string text : {std::string(100000, '(') + "1", std::string(100000, '-') + "1"}) {
    EXPECT_THROW(TieExpression(text, "--tie"), InputError);
  }
}

TEST(TieExpression, RefusesWhatItCannotReadNamingTheFlagAndThePlace) {
  for (const std::string text : {"", "2 +", "(1 + 2", "{/x", "{x}", "2 3", "nan", "2 ** 3", "{}"}) {
    SCOPED_TRACE(text);
    try {
      TieExpression(text, "--tie '/a=" + text + "'");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--tie '/a="), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("character"), std::string::npos) << e.what();
    }
  }
}

// Two bobs on rods, the second pushed sideways (so that the masses matter); its mass is tied to the first's,
// m_b = m_a / 2 + 0.1, in the gradient test.
json TwoBobs() {
  return {{"dimension", 2},
          {"bodies",
           {{{"name", "a"}, {"type", "particle"}, {"mass", 1.0}, {"position", {0.6, -0.8}}},
            {{"name", "b"}, {"type", "particle"}, {"mass", 0.3}, {"position", {1.6, -0.8}}}}},
          {"constraints",
           {{{"type", "distance"}, {"bodies", {"world", "a"}}, {"length", 1.0}},
            {{"type", "distance"}, {"bodies", {"a", "b"}}, {"length", 1.0}}}},
          {"effects",
           {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
            {{"type", "force"}, {"body", "b"}, {"value", {3.0, 0.0}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 0.01}, {"duration", 0.5}}}};
}

TEST(Ties, GradientsFollowTheTiedLoss) {
  const Scene scene = ParseScene(TwoBobs(), "two_bobs.json");
  ParameterSet parameters(scene, {"/bodies/0/mass"});
  parameters.Tie(scene, {"/bodies/1/mass={/bodies/0/mass}/2+0.1"});
  const Observations observations =
      MakeObservations("in memory", {"t", "b.x", "b.y"}, {{0.25, 1.2, -1.5}, {0.5, 0.9, -1.7}}, scene.model);
  const LossGradient jets = JetLossGradient(scene.model, parameters, observations);
  const LossGradient adjoint = AdjointLossGradient(scene.model, parameters, observations);
  // the loss with both masses moved together, by central differences
  const auto loss = [&](double m_a) {
    Model<double> model = scene.model;
    model.bodies[0].mass = m_a;
    model.bodies[1].mass = m_a / 2 + 0.1;
    return 0.5 * ObservationResiduals(model, observations).squaredNorm();
  };
  const double h = 1e-5;
  const double expected = (loss(1.0 + h) - loss(1.0 - h)) / (2 * h);
  ASSERT_GT(std::abs(expected), 1e-3);
  EXPECT_NEAR(jets.loss, loss(1.0), 1e-14);
  EXPECT_NEAR(adjoint.loss, loss(1.0), 1e-14);
  EXPECT_NEAR(jets.gradient[0], expected, 1e-6 * std::abs(expected));
  EXPECT_NEAR(adjoint.gradient[0], jets.gradient[0], 1e-8 * std::abs(expected));
  const LossGradient central = CentralDifferenceLossGradient(scene.model, parameters, observations);
  EXPECT_NEAR(central.gradient[0], expected, 1e-6 * std::abs(expected));
  // the scene written back carries the tied value
  json document = scene.document;
  parameters.WriteInto({0.8}, &document);
  EXPECT_DOUBLE_EQ(document["bodies"][1]["mass"].get<double>(), 0.5);
}

TEST(Ties, AreRefusedWhereTheyCannotHold) {
  const Scene scene = ParseScene(TwoBobs(), "two_bobs.json");
  const auto refused = [&](const std::vector<std::string>& ties, const std::string& part) {
    ParameterSet parameters(scene, {"/bodies/0/mass"});
    try {
      parameters.Tie(scene, ties);
      ADD_FAILURE() << "accepted " << ties.back();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--tie"), std::string::npos) << e.what();
    }
  };
  refused({"/bodies/1/mass"}, "expected PTR=EXPR");
  refused({"/bodies/1/mass={/bodies/7/mass}"}, "/bodies/7/mass");  // an unknown pointer
  refused({"/bodies/9/mass=1"}, "/bodies/9/mass");                 // an unknown target
  refused({"/bodies/0/mass=2"}, "is a parameter");                 // the target is an unknown
  refused({"/bodies/1/mass={/bodies/1/mass}*2"}, "itself");        // a loop
  refused({"/bodies/1/mass=1", "/bodies/1/mass=2"}, "tied twice");
  refused({"/bodies/1/mass={/constraints/1/length}", "/constraints/1/length=2"}, "a later tie");
  refused({"/simulation/step={/bodies/0/mass}"}, "/simulation/step");  // not differentiable
  refused({"/bodies/0/position/*={/bodies/0/mass}", "/bodies/5/*=1"}, "/bodies/5");
}

// A planar rod pendulum whose inertia is that of a rod of its mass, m L^2 / 12 (L = 0.6): identifying the mass
// alone from a guess with a 1 kg rod's inertia cannot reproduce a 0.7 kg rod's swing; tied, it does.
TEST(Ties, IdentifyARodsMassWithItsInertiaTiedToIt) {
  const auto rod = [](double mass, double inertia) {
    return json{
        {"dimension", 2},
        {"bodies",
         {{{"name", "rod"},
           {"type", "rigid"},
           {"mass", mass},
           {"inertia", inertia},
           {"position", {0.3, 0.0}},
           {"angle", 0.0}}}},
        {"constraints", {{{"type", "pin"}, {"bodies", {"world", "rod"}}, {"points", {{0.0, 0.0}, {-0.3, 0.0}}}}}},
        {"effects",
         {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
          {{"type", "torque"}, {"body", "rod"}, {"value", 0.5}}}},
        {"simulation", {{"integrator", "rk4"}, {"step", 0.005}, {"duration", 1.0}}}};
  };
  const Scene truth = ParseScene(rod(0.7, 0.7 * 0.36 / 12), "truth.json");
  std::vector<std::vector<double>> rows;
  RunOptions options;
  options.every = 10;
  Simulate<double>(truth.model, options, [&](const Sample<double>& s) {
    if (s.t > 0.0) rows.push_back({s.t, s.q[2]});
  });
  const Scene guess = ParseScene(rod(1.0, 0.36 / 12), "guess.json");
  const Observations data = MakeObservations("truth", {"t", "rod.angle"}, rows, guess.model);
  ParameterSet parameters(guess, {"/bodies/0/mass"});
  parameters.Tie(guess, {"/bodies/0/inertia={/bodies/0/mass}*0.36/12"});
  const IdentifyResult result = Identify(guess.model, parameters, {data}, IdentifySettings{});
  ASSERT_EQ(result.estimate.size(), 1u);
  EXPECT_NEAR(result.estimate[0], 0.7, 1e-6);
  EXPECT_LT(result.final_cost, 1e-12);
}

// One array following another element by element: a wildcard tie, "/*}" read as each element's index (a knot list
// shared by two effects is written the same way).
TEST(Ties, AWildcardTieMakesOneArrayFollowAnother) {
  const Scene scene = ParseScene(TwoBobs(), "two_bobs.json");
  ParameterSet parameters(scene, {"/bodies/0/position/0"});
  parameters.Tie(scene, {"/bodies/1/position/*={/bodies/0/position/*}+1"});
  Model<double> model = scene.model;
  parameters.Assign({0.7}, &model);
  EXPECT_DOUBLE_EQ(model.bodies[1].position[0], 1.7);
  EXPECT_DOUBLE_EQ(model.bodies[1].position[1], 0.2);
  json document = scene.document;
  parameters.WriteInto({0.7}, &document);
  EXPECT_DOUBLE_EQ(document["bodies"][1]["position"][0].get<double>(), 1.7);
  EXPECT_DOUBLE_EQ(document["bodies"][1]["position"][1].get<double>(), 0.2);
}

// A fit with one knot list shared by two effects: two torque schedules on a free planar disc, the second tied to the
// first knot by knot; fitting the first's three knots to the spin of the truth, where both are [1, 2, 1] N m,
// recovers them (untied, the second's zeros would leave half the torque unexplained).
TEST(Ties, AFitSharesOneKnotListBetweenTwoEffects) {
  const auto disc = [](const json& values) {
    const json schedule = {{"times", {0.0, 0.5, 1.0}}, {"values", values}};
    return json{{"dimension", 2},
                {"bodies",
                 {{{"name", "disc"},
                   {"type", "rigid"},
                   {"mass", 1.0},
                   {"inertia", 0.5},
                   {"position", {0.0, 0.0}},
                   {"angle", 0.0}}}},
                {"effects",
                 {{{"type", "torque"}, {"body", "disc"}, {"schedule", schedule}},
                  {{"type", "torque"}, {"body", "disc"}, {"schedule", schedule}}}},
                {"simulation", {{"integrator", "rk4"}, {"step", 0.01}, {"duration", 1.0}}}};
  };
  const Scene truth = ParseScene(disc({1.0, 2.0, 1.0}), "truth.json");
  std::vector<std::vector<double>> rows;
  RunOptions options;
  options.every = 10;
  Simulate<double>(truth.model, options, [&](const Sample<double>& s) {
    if (s.t > 0.0) rows.push_back({s.t, s.q[2], s.v[2]});
  });
  const Scene guess = ParseScene(disc({0.0, 0.0, 0.0}), "guess.json");
  const Observations targets = MakeObservations("truth", {"t", "disc.angle", "disc.omega"}, rows, guess.model);
  ParameterSet parameters(guess, {"/effects/0/schedule/values/*"});
  parameters.Tie(guess, {"/effects/1/schedule/values/*={/effects/0/schedule/values/*}"});
  const IdentifyResult result = Identify(guess.model, parameters, {targets}, IdentifySettings{});
  ASSERT_EQ(result.estimate.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(result.estimate[k], k == 1 ? 2.0 : 1.0, 1e-6) << k;
}

}  // namespace
}  // namespace tether
