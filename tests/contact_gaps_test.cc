// The gaps between shapes (contact_geometry.h, core_witnesses.h): every form against its closed form, with the rate
// of every feature against central differences of its gap along the motion; box-box and capsule-box gaps against
// the distance that alternating projections between the two shapes find, over random placements; and the broad
// phase, which leaves out only pairs that are apart.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "contact_scenes.h"
#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether {
namespace {

using nlohmann::json;

// Every feature's gap at the scene's initial state, its rate against central differences of the gap along the
// motion (q moved by +-h v, at constant v), and its row's velocity product (the gap's acceleration along that
// motion, v' = 0) against second differences.
std::vector<double> GapsAndCheckRates(const Model<double>& model) {
  const ContactGeometry geometry = BuildContactGeometry(model);
  const State<double> start = InitialState(model);
  BodyFrames<double> frames;
  UpdateFrames(model, start.q, start.v, true, &frames);
  auto gap_at = [&](const ContactFeature& f, double h) {
    VecX<double> q(start.q.size());
    Integrate(model, start.q, start.v, h, &q);
    BodyFrames<double> moved;
    UpdateFrames(model, q, start.v, false, &moved);
    return FeatureGapValue(model, f, moved, q);
  };
  std::vector<double> gaps;
  for (const ContactFeature& f : geometry.features) {
    const GapAndRate<double> gap = FeatureGap(model, f, frames, start.q, start.v);
    const double h = 1e-6, central = (gap_at(f, h) - gap_at(f, -h)) / (2 * h);
    EXPECT_NEAR(gap.rate, central, 1e-7) << geometry.pairs[f.pair].label << " feature " << f.vertex;
    gaps.push_back(gap.g);
    ConstraintRow<double> row;
    EvaluateContactRow(model, f, frames, start.q, start.v, true, &row);
    // relative where the gap's acceleration is large: the difference's rounding (the gaps' over H^2) grows with
    // the motion's speeds, and reached 3e-5 at -61 m/s^2 with clang's roundings (a larger H crosses the kinks where
    // a feature's closest points change edge)
    const double H = 2e-5, second = (gap_at(f, H) - 2 * gap.g + gap_at(f, -H)) / (H * H);
    EXPECT_NEAR(row.bias, second, 1e-5 * std::max(1.0, std::abs(second)))
        << geometry.pairs[f.pair].label << " form " << static_cast<int>(f.form) << " feature " << f.vertex;
  }
  return gaps;
}

json TwoShapes(const json& a, const json& b, const json& body_a, const json& body_b) {
  return {{"dimension", 3}, {"bodies", {body_a, body_b}}, {"shapes", {a, b}}};
}

TEST(ContactGaps, EachFormMatchesItsClosedForm) {
  const double s = std::sqrt(0.5);
  const json tilted = {std::cos(0.3), 0.0, std::sin(0.3), 0.0};  // 0.6 rad about y
  // a sphere and a capsule above a tilted plane of the world; a box's eight corners above the floor
  {
    const json scene = {
        {"dimension", 3},
        {"bodies", {Rigid3d("ball", {0.1, 0.2, 1.0}, {1, 0, 0, 0}, {1, 2, 3})}},
        {"shapes",
         {{{"body", "ball"}, {"type", "sphere"}, {"radius", 0.25}},
          {{"body", "world"}, {"type", "plane"}, {"position", {0.0, 0.0, 0.1}}, {"orientation", tilted}}}}};
    const std::vector<double> gaps = GapsAndCheckRates(Parse(scene));
    const Vec3<double> n(std::sin(0.6), 0.0, std::cos(0.6));  // the plane's z axis turned 0.6 rad about y
    ASSERT_EQ(gaps.size(), 1u);
    EXPECT_NEAR(gaps[0], n.dot(Vec3<double>(0.1, 0.2, 0.9)) - 0.25, 1e-14);
  }
  {
    const json scene = {{"dimension", 3},
                        {"bodies", {Rigid3d("rod", {0.0, 0.0, 1.0}, {s, 0.0, s, 0.0}, {1, -2, 0.5})}},  // x -> -z
                        {"shapes",
                         {{{"body", "rod"}, {"type", "capsule"}, {"radius", 0.1}, {"length", 0.6}},
                          {{"body", "world"}, {"type", "plane"}}}}};
    const std::vector<double> gaps = GapsAndCheckRates(Parse(scene));
    ASSERT_EQ(gaps.size(), 2u);
    EXPECT_NEAR(gaps[0], 1.3 - 0.1, 1e-14);  // the -x cap centre is up at 1.3
    EXPECT_NEAR(gaps[1], 0.7 - 0.1, 1e-14);
  }
  {
    const json scene = {{"dimension", 3},
                        {"bodies", {Rigid3d("box", {0.0, 0.0, 1.0}, {1, 0, 0, 0}, {0.5, 1, -1})}},
                        {"shapes",
                         {{{"body", "box"}, {"type", "box"}, {"size", {0.2, 0.4, 0.6}}, {"position", {0, 0, 0.05}}},
                          {{"body", "world"}, {"type", "plane"}}}}};
    const std::vector<double> gaps = GapsAndCheckRates(Parse(scene));
    ASSERT_EQ(gaps.size(), 8u);
    for (int k = 0; k < 8; ++k) EXPECT_NEAR(gaps[k], 1.05 + ((k >> 2) & 1 ? 0.3 : -0.3), 1e-14) << k;
  }
  // closest points: sphere-sphere, sphere-capsule (beside its segment and beyond its end), crossed capsules,
  // a sphere beside a box's face, off its edge, and with its centre inside
  const json ball = {{"body", "a"}, {"type", "sphere"}, {"radius", 0.1}};
  const json capsule = {{"body", "b"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 1.0}};
  const json box = {{"body", "b"}, {"type", "box"}, {"size", {0.4, 0.6, 0.8}}};
  struct Case {
    json a, b, body_a;
    double gap;
  };
  const json other = Rigid3d("b", {0.0, 0.0, 0.0}, {1, 0, 0, 0}, {0.2, 0.4, -0.3});
  const std::vector<Case> cases = {
      {ball,
       {{"body", "b"}, {"type", "sphere"}, {"radius", 0.2}},
       Rigid3d("a", {0.3, 0.4, 1.2}, {1, 0, 0, 0}),
       1.3 - 0.3},
      {ball, capsule, Rigid3d("a", {0.2, 0.0, 0.5}, {1, 0, 0, 0}), 0.5 - 0.15},
      {ball, capsule, Rigid3d("a", {0.8, 0.0, 0.4}, {1, 0, 0, 0}), 0.5 - 0.15},
      {{{"body", "a"}, {"type", "capsule"}, {"radius", 0.1}, {"length", 1.0}},
       capsule,
       Rigid3d("a", {0.1, 0.0, 0.7}, {s, 0.0, 0.0, s}),
       0.7 - 0.15},  // along y, 0.7 above
      {ball, box, Rigid3d("a", {0.1, 0.1, 0.9}, {1, 0, 0, 0}), 0.5 - 0.1},
      {ball, box, Rigid3d("a", {0.5, 0.6, 0.1}, {1, 0, 0, 0}), std::hypot(0.3, 0.3) - 0.1},
      {ball, box, Rigid3d("a", {0.15, 0.0, 0.1}, {1, 0, 0, 0}), -0.05 - 0.1},  // inside, nearest the +x face
  };
  for (const Case& c : cases) {
    const std::vector<double> gaps = GapsAndCheckRates(Parse(TwoShapes(c.a, c.b, c.body_a, other)));
    ASSERT_EQ(gaps.size(), 1u);
    EXPECT_NEAR(gaps[0], c.gap, 1e-14) << c.a.dump() << " " << c.b.dump();
  }
}

// The least gap of a model's features (each rate checked), and the form of the feature that has it.
std::pair<double, GapForm> LeastGap(const Model<double>& model) {
  const std::vector<double> gaps = GapsAndCheckRates(model);
  const ContactGeometry geometry = BuildContactGeometry(model);
  const size_t k = std::min_element(gaps.begin(), gaps.end()) - gaps.begin();
  return {gaps[k], geometry.features[k].form};
}

json Quaternion(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

Eigen::Quaterniond About(double angle, const Vec3<double>& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(ContactGaps, BoxesAndCapsulesAgainstBoxesMatchTheirClosedForms) {
  // box b: 0.4 x 0.6 x 0.8 at the origin (turned in some cases); shape a above it
  const json box_a = {{"body", "a"}, {"type", "box"}, {"size", {0.2, 0.4, 0.6}}};
  const json capsule_a = {{"body", "a"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 1.0}};
  const json short_capsule_a = {{"body", "a"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.3}};
  const Eigen::Quaterniond level = Eigen::Quaterniond::Identity(), ridge_x = About(M_PI / 4, Vec3<double>::UnitX()),
                           ridge_y = About(M_PI / 4, Vec3<double>::UnitY());
  const Eigen::Quaterniond corner_down =  // the corner (+, +, +) of a 0.2 x 0.4 x 0.6 box pointing down
      Eigen::Quaterniond::FromTwoVectors(Vec3<double>(0.1, 0.2, 0.3), Vec3<double>(0, 0, -1));
  const double half_diagonal = 0.5 * std::sqrt(0.2 * 0.2 + 0.4 * 0.4 + 0.6 * 0.6);
  struct Case {
    const char* what;
    json a;
    Eigen::Quaterniond turn_a, turn_b;
    Vec3<double> at;
    double gap;
    GapForm form;
  };
  const double s = std::sqrt(0.5);
  // a capsule across the face z = 0.4, tilted 0.05 rad: its gap at an edge y = +-0.3 along x is the distance of
  // its segment's line from the edge's, less its radius
  const Eigen::Quaterniond tilted_across = About(1.2, Vec3<double>::UnitZ()) * About(0.05, Vec3<double>::UnitY());
  const Vec3<double> along = tilted_across * Vec3<double>::UnitX();
  double across_gap = INFINITY;
  for (const double edge_y : {-0.3, 0.3}) {
    const Vec3<double> n = along.cross(Vec3<double>::UnitX()).normalized();
    across_gap = std::min(across_gap, std::abs(n.dot(Vec3<double>(0.0, 0.1 - edge_y, 0.6 - 0.4))) - 0.05);
  }
  const std::vector<Case> cases = {
      {"face over face", box_a, level, level, {0.05, 0.02, 1.0}, 1.0 - 0.3 - 0.4, GapForm::kVertexBox},
      {"a corner under b's face",
       box_a,
       corner_down,
       level,
       {0.0, 0.0, 1.0},
       1.0 - half_diagonal - 0.4,
       GapForm::kVertexBox},
      // a's ridge along x (at y = y_a + 0.1 s) over b's ridge along y (at x = 0.2 s): the edges cross
      {"crossed ridges",
       box_a,
       ridge_x,
       ridge_y,
       {0.2 * s + 0.01, -0.02, 1.2},
       1.2 - s * (0.2 + 0.3) - s * (0.2 + 0.4),
       GapForm::kCrossedEdges},
      {"crossed ridges overlapping",
       box_a,
       ridge_x,
       ridge_y,
       {0.2 * s + 0.01, -0.02, s * 1.1 - 0.01},
       -0.01,
       GapForm::kCrossedEdges},
      {"a capsule lying on a face",
       short_capsule_a,
       About(0.3, Vec3<double>::UnitZ()),
       level,
       {0.0, 0.1, 0.6},
       0.6 - 0.05 - 0.4,
       GapForm::kVertexBox},  // its caps within the face
      {"a capsule lying across a face",
       capsule_a,
       tilted_across,
       level,
       {0.0, 0.1, 0.6},
       across_gap,
       GapForm::kCrossedEdges},  // over both edges y = +-0.3 of the face, its -x end the lower
      {"a capsule across a ridge",
       capsule_a,
       level,
       ridge_y,
       {0.02, 0.1, 0.9},
       0.9 - 0.05 - s * (0.2 + 0.4),
       GapForm::kCrossedEdges},
      {"a capsule pressed into a ridge",
       capsule_a,
       level,
       ridge_y,
       {0.02, 0.1, s * 0.6 + 0.03},
       0.03 - 0.05,
       GapForm::kCrossedEdges},
      {"a capsule sunk into a ridge",
       capsule_a,
       level,
       ridge_y,
       {0.02, 0.1, s * 0.6 - 0.02},
       -0.02 - 0.05,
       GapForm::kCrossedEdges},
      {"a capsule under a corner",
       capsule_a,
       level,
       corner_down,
       {0.0, 0.0, -0.5},
       0.5 - half_diagonal - 0.05,
       GapForm::kVertexSegment},
  };
  const json a_box_b = {{"body", "b"}, {"type", "box"}, {"size", {0.4, 0.6, 0.8}}};
  for (const Case& c : cases) {
    json shape_b = a_box_b, shape_a = c.a;
    if (std::string(c.what) == "a capsule under a corner") {  // b is the turned box above the capsule
      shape_b["size"] = {0.2, 0.4, 0.6};
    }
    const json body_a = Rigid3d("a", {c.at.x(), c.at.y(), c.at.z()}, Quaternion(c.turn_a), {0.4, -0.3, 0.2});
    const json body_b = Rigid3d("b", {0.0, 0.0, 0.0}, Quaternion(c.turn_b), {-0.1, 0.5, 0.3});
    const auto [gap, form] = LeastGap(Parse(TwoShapes(shape_a, shape_b, body_a, body_b)));
    EXPECT_NEAR(gap, c.gap, 1e-13) << c.what;
    EXPECT_EQ(form, c.form) << c.what;
  }
  // in the plane: a box's corner against a box's face, a capsule's side against a box's corner
  const json planar = {{"dimension", 2},
                       {"bodies",
                        {{{"name", "a"},
                          {"type", "rigid"},
                          {"mass", 1.0},
                          {"inertia", 0.1},
                          {"position", {0.1, 1.0}},
                          {"angle", M_PI / 4},
                          {"velocity", {0.2, -0.3}},
                          {"angular_velocity", 0.7}},
                         {{"name", "b"},
                          {"type", "rigid"},
                          {"mass", 1.0},
                          {"inertia", 0.1},
                          {"position", {0.0, 0.0}},
                          {"angle", 0.0},
                          {"velocity", {0.0, 0.1}},
                          {"angular_velocity", -0.4}},
                         {{"name", "c"},
                          {"type", "rigid"},
                          {"mass", 1.0},
                          {"inertia", 0.1},
                          {"position", {3.0, 0.5}},
                          {"angle", 0.0},
                          {"velocity", {0.0, 0.1}},
                          {"angular_velocity", 0.3}},
                         {{"name", "d"},
                          {"type", "rigid"},
                          {"mass", 1.0},
                          {"inertia", 0.1},
                          {"position", {3.1, 0.0}},
                          {"angle", M_PI / 4},
                          {"velocity", {0.1, 0.0}},
                          {"angular_velocity", 0.2}}}},
                       {"shapes",
                        {{{"body", "a"}, {"type", "box"}, {"size", {0.2, 0.2}}},
                         {{"body", "b"}, {"type", "box"}, {"size", {1.0, 0.6}}},
                         {{"body", "c"}, {"type", "capsule"}, {"radius", 0.1}, {"length", 2.0}},
                         {{"body", "d"}, {"type", "box"}, {"size", {0.4, 0.4}}}}},
                       {"contact",
                        {{"exclude", json::array({json::array({"a", "c"}), json::array({"a", "d"}),
                                                  json::array({"b", "c"}), json::array({"b", "d"})})}}}};
  const Model<double> model = Parse(planar);
  const std::vector<double> gaps = GapsAndCheckRates(model);
  const ContactGeometry geometry = BuildContactGeometry(model);
  ASSERT_EQ(geometry.pairs.size(), 2u);
  double least[2] = {INFINITY, INFINITY};
  for (size_t k = 0; k < gaps.size(); ++k)
    least[geometry.features[k].pair] = std::min(least[geometry.features[k].pair], gaps[k]);
  EXPECT_NEAR(least[0], 1.0 - 0.1 * std::sqrt(2.0) - 0.3, 1e-13);  // a's corner down on b's top face
  EXPECT_NEAR(least[1], 0.5 - 0.2 * std::sqrt(2.0) - 0.1, 1e-13);  // d's corner up against c's side
}

// The closest points of two convex sets by alternating projections x <- P_A(y), y <- P_B(x) (they converge to a
// closest pair), as an independent measure of the distance.
using Projection = std::function<Vec3<double>(const Vec3<double>&)>;
double ProjectedDistance(const Projection& onto_a, const Projection& onto_b) {
  Vec3<double> x = Vec3<double>::Zero(), y = onto_b(x);
  for (int k = 0; k < 200000; ++k) {
    const Vec3<double> x_next = onto_a(y), y_next = onto_b(x_next);
    const bool still = (x_next - x).norm() < 1e-15 && (y_next - y).norm() < 1e-15;
    x = x_next;
    y = y_next;
    if (still) break;
  }
  return (x - y).norm();
}

Projection OntoBox(const Vec3<double>& centre, const Mat3<double>& R, const Vec3<double>& half) {
  return [=](const Vec3<double>& p) {
    const Vec3<double> local = R.transpose() * (p - centre);
    return Vec3<double>(centre + R * local.cwiseMax(-half).cwiseMin(half));
  };
}

Projection OntoCapsule(const Vec3<double>& centre, const Mat3<double>& R, double length, double radius) {
  return [=](const Vec3<double>& p) {
    const Vec3<double> axis = R.col(0);
    const Vec3<double> core = centre + axis * std::clamp(axis.dot(p - centre), -length / 2, length / 2);
    const Vec3<double> out = p - core;
    return out.norm() <= radius ? p : Vec3<double>(core + out.normalized() * radius);
  };
}

TEST(ContactGaps, BoxBoxAndCapsuleBoxGapsAreTheDistanceAlternatingProjectionsFind) {
  // random placements of each pair: where the shapes are apart the least gap of the pair's features is their
  // distance; where they overlap, as shapes do for a step before the contact pushes them apart (by less than 2 cm
  // here), the least gap is negative
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> size(0.1, 0.5), reach(0.0, 1.0);
  const auto turn = [&] {
    return Eigen::Quaterniond(normal(random), normal(random), normal(random), normal(random)).normalized();
  };
  int apart = 0, overlapping = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const bool capsule = trial % 2 == 1;
    const Vec3<double> half_a(size(random) / 2, size(random) / 2, size(random) / 2);
    const Vec3<double> half_b(size(random) / 2, size(random) / 2, size(random) / 2);
    const Eigen::Quaterniond turn_a = turn(), turn_b = turn();
    const Vec3<double> at = Vec3<double>(normal(random), normal(random), normal(random)).normalized() * reach(random);
    const json shape_a =
        capsule ? json{{"body", "a"}, {"type", "capsule"}, {"radius", half_a.x()}, {"length", 2 * half_a.y()}}
                : json{{"body", "a"}, {"type", "box"}, {"size", {2 * half_a.x(), 2 * half_a.y(), 2 * half_a.z()}}};
    const json shape_b = {{"body", "b"}, {"type", "box"}, {"size", {2 * half_b.x(), 2 * half_b.y(), 2 * half_b.z()}}};
    const json body_a = Rigid3d("a", {at.x(), at.y(), at.z()}, Quaternion(turn_a), {0.4, -0.3, 0.2});
    const json body_b = Rigid3d("b", {0.0, 0.0, 0.0}, Quaternion(turn_b), {-0.1, 0.5, 0.3});
    const auto [gap, form] = LeastGap(Parse(TwoShapes(shape_a, shape_b, body_a, body_b)));
    const Mat3<double> R_a = turn_a.toRotationMatrix(), R_b = turn_b.toRotationMatrix();
    const auto distance = [&](const Vec3<double>& centre) {
      const Projection onto_a =
          capsule ? OntoCapsule(centre, R_a, 2 * half_a.y(), half_a.x()) : OntoBox(centre, R_a, half_a);
      return ProjectedDistance(onto_a, OntoBox(Vec3<double>::Zero(), R_b, half_b));
    };
    if (distance(at) > 1e-6) {
      ++apart;
      EXPECT_NEAR(gap, distance(at), 1e-9) << "trial " << trial;
    } else if (distance(at + 0.02 * at.normalized()) > 1e-6) {  // a shallow overlap, not one passed through
      ++overlapping;
      EXPECT_LT(gap, 0.0) << "trial " << trial;
    }
  }
  EXPECT_GT(apart, 1000);
  EXPECT_GT(overlapping, 20);
}

TEST(ContactGaps, TheBroadPhaseKeepsEveryPairThatMayTouchAndLeavesOutOnlyPairsApart) {
  // 40 particles with spheres, capsules and boxes scattered over a floor: the pairs left out all have positive gaps,
  // and the pairs kept are those whose bounding spheres overlap (checked pair by pair)
  std::mt19937 random(7);
  std::uniform_real_distribution<double> place(-1.0, 1.0), height(0.0, 0.6);
  json scene = {{"dimension", 3}, {"bodies", json::array()}, {"shapes", json::array()}};
  for (int k = 0; k < 40; ++k) {
    const std::string name = "b" + std::to_string(k);
    scene["bodies"].push_back(Particle(name, {place(random), place(random), height(random)}));
    json shape = {{"body", name}, {"type", "sphere"}, {"radius", 0.1}};
    if (k % 3 == 1) shape = {{"body", name}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.2}};
    if (k % 3 == 2) shape = {{"body", name}, {"type", "sphere"}, {"radius", 0.15}};
    scene["shapes"].push_back(shape);
  }
  scene["shapes"].push_back({{"body", "world"}, {"type", "plane"}});
  const Model<double> model = Parse(scene);
  const ContactGeometry geometry = BuildContactGeometry(model);
  const State<double> start = InitialState(model);
  BodyFrames<double> frames;
  UpdateFrames(model, start.q, start.v, false, &frames);
  std::vector<char> near;
  NearPairs(model, geometry, frames, start.q, 0.0, &near);
  int kept = 0;
  for (size_t p = 0; p < geometry.pairs.size(); ++p) kept += near[p];
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, static_cast<int>(geometry.pairs.size()) / 4);  // most pairs are apart
  double least_left_out = INFINITY;
  for (const ContactFeature& f : geometry.features) {
    if (!near[f.pair]) least_left_out = std::min(least_left_out, FeatureGapValue(model, f, frames, start.q));
  }
  EXPECT_GT(least_left_out, 0.0);
  const auto bound = [&](int shape) {
    const Shape<double>& s = model.shapes[shape];
    return s.radius + (s.type == ShapeType::kCapsule ? s.length / 2 : 0.0);
  };
  for (size_t p = 0; p < geometry.pairs.size(); ++p) {
    const ContactPair& pair = geometry.pairs[p];
    if (model.shapes[pair.b].type == ShapeType::kPlane) {
      EXPECT_EQ(near[p], start.q[3 * pair.a + 2] <= bound(pair.a)) << pair.label;
      continue;
    }
    const double apart = (start.q.segment<3>(3 * pair.a) - start.q.segment<3>(3 * pair.b)).norm();
    EXPECT_EQ(near[p], apart <= bound(pair.a) + bound(pair.b)) << pair.label;
  }
}

}  // namespace
}  // namespace tether
