// tether against MuJoCo on contact, side by side in one run (bench/peer/README.md, "Contact"): a ball and a box
// dropped on a plane, and MuJoCo's own humanoid (its file, its geoms) dropped 0.2 m onto its floor, at h = 1 ms and
// h = 5 ms (MuJoCo's humanoid's own step), 2 s each.
//
// Every case first runs once untimed, observing every step:
//   deepest_mm      the deepest overlap of any shape with the floor, mm (tether: from the bodies' frames and the
//                   scene's shapes; MuJoCo: the most negative contact distance);
//   restitution     the ball's rebound speed over its impact speed at the first impact (asked: 0.5);
//   apex_error      the ball's first rebound apex against the closed form e^2 h0 of the restitution asked, as a
//                   fraction of h0 (the impact's energy error);
//   rest_error_mm   the box's height at the end against its half edge (resting on its face), mm.
// Then the run is timed unobserved; the counter cpu_ms_per_s is CPU milliseconds per simulated second.
//
// Settings. tether: Baumgarte gains alpha = 100, beta = 2500 (MuJoCo's solref time constant 0.02 at critical
// damping), the ball's restitution 0.5, the box's 0; "stepping" (velocity-level impulses) with symplectic Euler,
// and for the ball and the box also "events" (impacts located, rk4). MuJoCo: its defaults (Newton solver, soft
// contacts, solref 0.02, solimp 0.9 0.95 0.001), semi-implicit Euler; the ball's restitution asked through
// solref's damping ratio, zeta = -ln e / sqrt(pi^2 + ln^2 e) (a damped spring's rebound is exp(-zeta pi /
// sqrt(1 - zeta^2)) = e); the humanoid's file as it is (its contact solref 0.015, its geoms' friction 0.7 against
// the floor's 1), with h changed and its root raised 0.2 m.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <sstream>
#include <string>

#include "mujoco_models.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::bench {
namespace {

using nlohmann::json;

constexpr double kDuration = 2.0;     // s
constexpr double kRestitution = 0.5;  // the ball's, asked
constexpr double kDropHeight = 1.0;   // the ball's lowest point above the floor, m
constexpr double kRadius = 0.1;       // the ball's, m
constexpr double kHalfEdge = 0.1;     // the box's, m
constexpr double kHumanoidRaise = 0.2;
constexpr double kG = 9.81;

enum class Case { kBall, kBox, kHumanoid };

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// What the untimed run saw of the motion: the deepest overlap, and the ball's first impact and rebound.
class Watch {
 public:
  void Step(double deepest, double vz, double z) {
    deepest_ = std::min(deepest_, deepest);
    if (phase_ == 0 && vz < impact_speed_) impact_speed_ = vz;  // falling faster and faster
    if (phase_ == 0 && vz > 0.0) phase_ = 1;                    // rebounded
    if (phase_ == 1) {
      rebound_speed_ = std::max(rebound_speed_, vz);
      apex_ = std::max(apex_, z);
      if (vz < 0.0) phase_ = 2;
    }
    last_z_ = z;
  }
  void Report(benchmark::State& state, Case c) const {
    state.counters["deepest_mm"] = -1e3 * deepest_;
    if (c == Case::kBall) {
      state.counters["restitution"] = rebound_speed_ / -impact_speed_;
      state.counters["apex_error"] = (apex_ - kRadius - kRestitution * kRestitution * kDropHeight) / kDropHeight;
    }
    if (c == Case::kBox) state.counters["rest_error_mm"] = 1e3 * (last_z_ - kHalfEdge);
  }

 private:
  double deepest_ = 0.0, impact_speed_ = 0.0, rebound_speed_ = 0.0, apex_ = 0.0, last_z_ = 0.0;
  int phase_ = 0;
};

// ---------------------------------------------------------------------------------------------------------------
// tether

json Floor() { return {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}; }

json Simulation(double step, bool events) {
  return {{"integrator", events ? "rk4" : "symplectic_euler"},
          {"step", step},
          {"duration", kDuration},
          {"contact", events ? "events" : "stepping"}};
}

const json kStabilization = {{"method", "baumgarte"}, {"alpha", 100.0}, {"beta", 2500.0}};

json TetherScene(Case c, double step, bool events) {
  const json gravity = {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}};
  if (c == Case::kBall) {
    return {
        {"dimension", 3},
        {"bodies",
         {{{"name", "ball"}, {"type", "particle"}, {"mass", 1.0}, {"position", {0.0, 0.0, kRadius + kDropHeight}}}}},
        {"shapes",
         {{{"name", "ball_surface"},
           {"body", "ball"},
           {"type", "sphere"},
           {"radius", kRadius},
           {"restitution", kRestitution}},
          Floor()}},
        {"effects", gravity},
        {"simulation", Simulation(step, events)},
        {"stabilization", kStabilization}};
  }
  if (c == Case::kBox) {  // 1 kg, tilted 0.1 rad about x so that its corners land one after another
    const double inertia = 2.0 * kHalfEdge * kHalfEdge / 3.0;  // m (2a)^2 / 6
    return {{"dimension", 3},
            {"bodies",
             {{{"name", "box"},
               {"type", "rigid"},
               {"mass", 1.0},
               {"inertia", {inertia, inertia, inertia}},
               {"position", {0.0, 0.0, 0.5}},
               {"orientation", {std::cos(0.05), std::sin(0.05), 0.0, 0.0}}}}},
            {"shapes",
             {{{"name", "box_surface"},
               {"body", "box"},
               {"type", "box"},
               {"size", {2 * kHalfEdge, 2 * kHalfEdge, 2 * kHalfEdge}}},
              Floor()}},
            {"effects", gravity},
            {"simulation", Simulation(step, events)},
            {"stabilization", kStabilization}};
  }
  importers::ImportOptions options;
  json scene = importers::ImportModel(kMujocoHumanoidFile, options).scene;
  for (json& body : scene["bodies"]) body["position"][2] = body["position"][2].get<double>() + kHumanoidRaise;
  scene["simulation"] = Simulation(step, events);
  scene["stabilization"] = kStabilization;
  return scene;
}

// The lowest point of every shape against the floor z = 0 (spheres, capsules, boxes), from the bodies' frames.
double DeepestTether(const Model<double>& model, const json& shapes, const Sample<double>& s) {
  double deepest = 0.0;
  for (const json& shape : shapes) {
    if (shape["body"] == "world" || !shape.value("contact", true)) continue;
    int body = 0;
    while (model.bodies[body].name != shape["body"].get<std::string>()) ++body;
    const Body<double>& b = model.bodies[body];
    const Vec3<double> origin = s.q.segment<3>(b.q_offset);
    const Mat3<double> r_wb = b.kind == BodyKind::kParticle ? Mat3<double>::Identity() : s.frames[body].R_WB;
    const json position = shape.value("position", json::array({0.0, 0.0, 0.0}));
    const json q = shape.value("orientation", json::array({1.0, 0.0, 0.0, 0.0}));
    const Mat3<double> r_ws =
        r_wb * Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>())
                   .toRotationMatrix();
    const Vec3<double> centre =
        origin + r_wb * Vec3<double>(position[0].get<double>(), position[1].get<double>(), position[2].get<double>());
    double lowest = centre.z();
    if (shape["type"] == "sphere") {
      lowest -= shape["radius"].get<double>();
    } else if (shape["type"] == "capsule") {
      lowest -= std::abs(r_ws(2, 0)) * shape["length"].get<double>() / 2 + shape["radius"].get<double>();
    } else if (shape["type"] == "box") {
      for (int k = 0; k < 3; ++k) lowest -= std::abs(r_ws(2, k)) * shape["size"][k].get<double>() / 2;
    }
    deepest = std::min(deepest, lowest);
  }
  return deepest;
}

void Tether(benchmark::State& state, Case c, double step, bool events) {
  const json document = TetherScene(c, step, events);
  const Scene scene = ParseScene(document, "contact_bench");
  Watch watch;
  try {
    Simulate<double>(scene.model, RunOptions{}, [&](const Sample<double>& s) {
      const Body<double>& first = scene.model.bodies[0];
      watch.Step(DeepestTether(scene.model, document["shapes"], s), s.v[first.v_offset + 2], s.q[first.q_offset + 2]);
    });
  } catch (const SimulationDiverged& e) {
    state.SkipWithError(e.what());
    return;
  }
  RunOptions quiet;
  quiet.every = 1 << 30;
  double cpu = 0.0;
  for (auto _ : state) {
    const double start = CpuSeconds();
    Simulate<double>(scene.model, quiet, [](const Sample<double>& s) { benchmark::DoNotOptimize(s.q.data()); });
    cpu += CpuSeconds() - start;
  }
  state.counters["cpu_ms_per_s"] = 1e3 * cpu / static_cast<double>(state.iterations()) / kDuration;
  watch.Report(state, c);
}

// ---------------------------------------------------------------------------------------------------------------
// MuJoCo

std::string MujocoXml(Case c, double step) {
  const double zeta =
      -std::log(kRestitution) / std::sqrt(M_PI * M_PI + std::log(kRestitution) * std::log(kRestitution));
  std::ostringstream xml;
  xml.precision(17);
  xml << "<mujoco><option timestep=\"" << step
      << R"(" gravity="0 0 -9.81" integrator="Euler"/><worldbody><geom type="plane" size="0 0 1"/>)";
  if (c == Case::kBall) {
    xml << "<body pos=\"0 0 " << kRadius + kDropHeight << "\"><freejoint/><geom type=\"sphere\" size=\"" << kRadius
        << "\" mass=\"1\" solref=\"0.02 " << zeta << "\"/></body>";
  } else {
    xml << "<body pos=\"0 0 0.5\" quat=\"" << std::cos(0.05) << " " << std::sin(0.05)
        << R"( 0 0"><freejoint/><geom type="box" size=")" << kHalfEdge << " " << kHalfEdge << " " << kHalfEdge
        << R"(" mass="1"/></body>)";
  }
  xml << "</worldbody></mujoco>";
  return xml.str();
}

MjModelPtr LoadCase(Case c, double step) {
  char error[1000] = "";
  mjModel* model = nullptr;
  if (c == Case::kHumanoid) {
    model = mj_loadXML(kMujocoHumanoidFile, nullptr, error, sizeof(error));
  } else {
    std::unique_ptr<mjVFS> vfs(new mjVFS);
    mj_defaultVFS(vfs.get());
    const std::string xml = MujocoXml(c, step);
    mj_makeEmptyFileVFS(vfs.get(), "case.xml", static_cast<int>(xml.size()));
    std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[vfs->nfile - 1]));
    model = mj_loadXML("case.xml", vfs.get(), error, sizeof(error));
    mj_deleteVFS(vfs.get());
  }
  if (model == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
  model->opt.timestep = step;
  return MjModelPtr(model);
}

MjDataPtr Start(const mjModel& model, Case c) {
  MjDataPtr data(mj_makeData(&model));
  if (c == Case::kHumanoid) data->qpos[2] += kHumanoidRaise;  // the root's free joint
  mj_forward(&model, data.get());
  return data;
}

void Mujoco(benchmark::State& state, Case c, double step) {
  const auto model = LoadCase(c, step);
  const int steps = static_cast<int>(std::lround(kDuration / step));
  Watch watch;
  {
    const auto data = Start(*model, c);
    for (int k = 0; k < steps; ++k) {
      mj_step(model.get(), data.get());
      double deepest = 0.0;
      for (int i = 0; i < data->ncon; ++i) deepest = std::min(deepest, data->contact[i].dist);
      watch.Step(deepest, data->qvel[2], data->qpos[2]);
    }
  }
  double cpu = 0.0;
  for (auto _ : state) {
    const auto data = Start(*model, c);
    const double start = CpuSeconds();
    for (int k = 0; k < steps; ++k) mj_step(model.get(), data.get());
    cpu += CpuSeconds() - start;
    benchmark::DoNotOptimize(data->qpos);
  }
  state.counters["cpu_ms_per_s"] = 1e3 * cpu / static_cast<double>(state.iterations()) / kDuration;
  watch.Report(state, c);
}

// Names are CASE/STEP/ENGINE: ball/h1ms/tether_stepping, box/h5ms/mujoco, humanoid/h1ms/tether_stepping, ...
void Register() {
  for (double step : {1e-3, 5e-3}) {
    const std::string h = step == 1e-3 ? "/h1ms" : "/h5ms";
    auto add = [](const std::string& name, auto&& function, auto... arguments) {
      benchmark::RegisterBenchmark(name.c_str(), function, arguments...)->Unit(benchmark::kMillisecond)->Iterations(3);
    };
    for (auto [c, name] : {std::pair{Case::kBall, "ball"}, std::pair{Case::kBox, "box"}}) {
      add(name + h + "/tether_events", Tether, c, step, true);
      add(name + h + "/tether_stepping", Tether, c, step, false);
      add(name + h + "/mujoco", Mujoco, c, step);
    }
    add("humanoid" + h + "/tether_stepping", Tether, Case::kHumanoid, step, false);
    add("humanoid" + h + "/mujoco", Mujoco, Case::kHumanoid, step);
  }
}

}  // namespace
}  // namespace tether::bench

int main(int argc, char** argv) {
  tether::bench::Register();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
