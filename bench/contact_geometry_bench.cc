// What the narrow phase costs (contact_geometry.h): every feature's gap of one pair of shapes, at 1000 random
// placements of the pair near contact (one item a pair measured), for box-box (8 + 8 corners against a box, 4
// crossed-edge ranks), capsule-box (2 caps, 8 corners against the segment, 2 ranks) and, for scale, sphere-box.
// docs/contact.md compares them with FCL's box-box (scripts in the docs' "Closed forms" paragraph).
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether::bench {
namespace {

using nlohmann::json;

constexpr int kPlacements = 1000;

json Box(const std::string& body, double x, double y, double z) {
  return {{"body", body}, {"type", "box"}, {"size", {x, y, z}}};
}

// Two rigid bodies a and b with the shapes given, and kPlacements configurations: b at the origin, a within 0.6 m
// of it, both turned at random.
void PairGaps(benchmark::State& state, const json& shape_a, const json& shape_b) {
  const json rigid = {{"type", "rigid"}, {"mass", 1.0}, {"inertia", {0.01, 0.01, 0.01}}, {"position", {0, 0, 0}}};
  json a = rigid, b = rigid;
  a["name"] = "a";
  b["name"] = "b";
  const json scene = {{"dimension", 3}, {"bodies", {a, b}}, {"shapes", {shape_a, shape_b}}};
  const Model<double> model = ParseScene(scene, "bench.json").model;
  const ContactGeometry geometry = BuildContactGeometry(model);
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> reach(0.0, 0.6);
  std::vector<VecX<double>> placements;
  for (int k = 0; k < kPlacements; ++k) {
    VecX<double> q = InitialState(model).q;
    const Vec3<double> at = Vec3<double>(normal(random), normal(random), normal(random)).normalized() * reach(random);
    for (int body = 0; body < 2; ++body) {
      const Vec4<double> turn =
          Vec4<double>(normal(random), normal(random), normal(random), normal(random)).normalized();
      q.segment<3>(model.bodies[body].q_offset) = body == 0 ? at : Vec3<double>(Vec3<double>::Zero());
      q.segment<4>(model.bodies[body].q_offset + 3) = turn;
    }
    placements.push_back(q);
  }
  BodyFrames<double> frames;
  int k = 0;
  for (auto _ : state) {
    const VecX<double>& q = placements[k++ % kPlacements];
    UpdateFrames(model, q, q, false, &frames);
    double least = 1e300;
    for (const ContactFeature& feature : geometry.features) {
      least = std::min(least, FeatureGapValue(model, feature, frames, q));
    }
    benchmark::DoNotOptimize(least);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["features"] = static_cast<double>(geometry.features.size());
}

void BoxBox(benchmark::State& state) { PairGaps(state, Box("a", 0.2, 0.3, 0.4), Box("b", 0.3, 0.4, 0.5)); }
void CapsuleBox(benchmark::State& state) {
  PairGaps(state, {{"body", "a"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.4}}, Box("b", 0.3, 0.4, 0.5));
}
void SphereBox(benchmark::State& state) {
  PairGaps(state, {{"body", "a"}, {"type", "sphere"}, {"radius", 0.1}}, Box("b", 0.3, 0.4, 0.5));
}

BENCHMARK(BoxBox)->Unit(benchmark::kNanosecond);
BENCHMARK(CapsuleBox)->Unit(benchmark::kNanosecond);
BENCHMARK(SphereBox)->Unit(benchmark::kNanosecond);

}  // namespace
}  // namespace tether::bench
