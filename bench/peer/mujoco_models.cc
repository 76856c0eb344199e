#include "mujoco_models.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "bench_models.h"
#include "humanoid_tree.h"
#include "rssr_linkage.h"

namespace tether::bench {
namespace {

// `rows`: the equality constraint rows, which MuJoCo's constraint buffer (njmax, 500 by default) must hold;
// beyond it MuJoCo drops constraints with a warning, and a chain falls apart
std::string Options(bool rk4, int rows, const MujocoSettings& s) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<option timestep=\"" << s.step << R"(" gravity="0 0 -9.81" solver="Newton" iterations="100" )"
      << R"(tolerance="1e-8" integrator=")" << (rk4 ? "RK4" : "Euler") << R"("><flag energy="enable"/></option>)"
      << "<size njmax=\"" << std::max(rows, 500) << "\"/>"
      << "<default><equality solref=\"" << s.time_constant << " 1\" solimp=\"" << s.impedance << " "
      << std::min(s.impedance + 0.05, 1.0) << " 0.001\"/></default>";
  return xml.str();
}

std::string Site(const std::string& name, double x = 0.0) {
  return "<site name=\"" + name + "\" pos=\"" + std::to_string(x) + " 0 0\"/>";
}

// mass i at (i + 1, 0, 0) on three slides; link i a tendon from site m(i-1) (the anchor for i = 0) to m(i)
std::string ChainOfSlides(int n, bool rk4, const MujocoSettings& settings) {
  std::ostringstream xml;
  xml << R"(<mujoco model="chain_of_slides">)" << Options(rk4, n, settings) << "<worldbody>" << Site("m-1");
  for (int i = 0; i < n; ++i) {
    xml << "<body name=\"p" << i << "\" pos=\"" << i + 1 << " 0 0\">"
        << R"(<joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/><joint type="slide" axis="0 0 1"/>)"
        << R"(<inertial pos="0 0 0" mass="1" diaginertia="1e-6 1e-6 1e-6"/>)" << Site("m" + std::to_string(i))
        << "</body>";
  }
  xml << "</worldbody><tendon>";
  for (int i = 0; i < n; ++i) {
    xml << "<spatial name=\"t" << i << "\"><site site=\"m" << i - 1 << "\"/><site site=\"m" << i << "\"/></spatial>";
  }
  xml << "</tendon><equality>";
  for (int i = 0; i < n; ++i) xml << "<tendon tendon1=\"t" << i << "\"/>";
  xml << "</equality></mujoco>";
  return xml.str();
}

// link i a free body from (i, 0, 0) (site b<i>) to its mass at (i + 1, 0, 0) (site m<i>); its base is connected
// to the previous mass (the world's origin for i = 0)
std::string ChainOfFreeBodies(int n, bool rk4, const MujocoSettings& settings) {
  std::ostringstream xml;
  xml << R"(<mujoco model="chain_of_free_bodies">)" << Options(rk4, 3 * n, settings) << "<worldbody>" << Site("m-1");
  for (int i = 0; i < n; ++i) {
    xml << "<body name=\"p" << i << "\" pos=\"" << i << " 0 0\"><freejoint/>"
        << R"(<inertial pos="1 0 0" mass="1" diaginertia="1e-6 1e-6 1e-6"/>)" << Site("b" + std::to_string(i))
        << Site("m" + std::to_string(i), 1.0) << "</body>";
  }
  xml << "</worldbody><equality>";
  for (int i = 0; i < n; ++i) {
    xml << "<connect body1=\"p" << i << "\" body2=\"" << (i == 0 ? std::string("world") : "p" + std::to_string(i - 1))
        << "\" anchor=\"0 0 0\"/>";
  }
  xml << "</equality></mujoco>";
  return xml.str();
}

std::string Vector(const Vec3<double>& v) {
  std::ostringstream out;
  out.precision(17);
  out << v.x() << " " << v.y() << " " << v.z();
  return out.str();
}

// n parallelograms in the x-z plane: crank i hinged to the ground at (i, 0, 0), coupler i hinged to crank i's tip,
// and a connect equality closing each loop at crank i + 1's tip
std::string FourBar(int n, bool rk4, const MujocoSettings& settings) {
  std::ostringstream xml;
  xml << R"(<mujoco model="four_bar">)" << Options(rk4, 3 * n, settings) << "<worldbody>";
  for (int i = 0; i <= n; ++i) {
    xml << "<body name=\"crank" << i << "\" pos=\"" << i << R"( 0 0"><joint type="hinge" axis="0 1 0"/>)"
        << R"(<inertial pos="0 0 0.5" mass="1" diaginertia="0.0833333333333333 0.0833333333333333 1e-6"/>)"
        << "<site name=\"crank" << i << "_tip\" pos=\"0 0 1\"/>";
    if (i < n) {
      xml << "<body name=\"coupler" << i << R"(" pos="0 0 1"><joint type="hinge" axis="0 1 0"/>)"
          << R"(<inertial pos="0.5 0 0" mass="1" diaginertia="1e-6 0.0833333333333333 0.0833333333333333"/>)"
          << "<site name=\"coupler" << i << "_end\" pos=\"1 0 0\"/></body>";
    }
    xml << "</body>";
  }
  xml << "</worldbody><equality>";
  for (int i = 0; i < n; ++i) {
    xml << "<connect body1=\"coupler" << i << "\" body2=\"crank" << i + 1 << "\" anchor=\"1 0 0\"/>";
  }
  xml << "</equality></mujoco>";
  return xml.str();
}

// rssr_linkage.h's linkage: the crank and the rocker on hinges, the coupler on a ball joint at the crank's tip and a
// connect equality (the other ball joint) at the rocker's tip; body frames at the joints, axes the world's
std::string SpatialFourBar(bool rk4, const MujocoSettings& settings) {
  const Rssr r = RssrLinkage();
  std::ostringstream xml;
  xml.precision(17);
  auto inertial = [&xml](const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& origin) {
    const Mat3<double> inertia = RodInertiaInWorld(a, b);
    xml << "<inertial pos=\"" << Vector(0.5 * (a + b) - origin) << "\" mass=\"1\" fullinertia=\"" << inertia(0, 0)
        << " " << inertia(1, 1) << " " << inertia(2, 2) << " " << inertia(0, 1) << " " << inertia(0, 2) << " "
        << inertia(1, 2) << "\"/>";
  };
  xml << R"(<mujoco model="rssr">)" << Options(rk4, 3, settings) << "<worldbody>";
  xml << "<body name=\"crank\" pos=\"" << Vector(r.crank_pivot) << R"("><joint type="hinge" axis=")"
      << Vector(r.crank_axis) << "\"/>";
  inertial(r.crank_pivot, r.crank_tip, r.crank_pivot);
  xml << "<body name=\"coupler\" pos=\"" << Vector(r.crank_tip - r.crank_pivot) << R"("><joint type="ball"/>)";
  inertial(r.crank_tip, r.rocker_tip, r.crank_tip);
  xml << "<site name=\"coupler_end\" pos=\"" << Vector(r.rocker_tip - r.crank_tip) << "\"/></body></body>";
  xml << "<body name=\"rocker\" pos=\"" << Vector(r.rocker_pivot) << R"("><joint type="hinge" axis=")"
      << Vector(r.rocker_axis) << "\"/>";
  inertial(r.rocker_pivot, r.rocker_tip, r.rocker_pivot);
  xml << "<site name=\"rocker_tip\" pos=\"" << Vector(r.rocker_tip - r.rocker_pivot) << "\"/></body>";
  xml << R"(</worldbody><equality><connect body1="coupler" body2="rocker" anchor=")"
      << Vector(r.rocker_tip - r.crank_tip) << "\"/></equality></mujoco>";
  return xml.str();
}

// rods of 1 kg, 1 m and radius 2 cm on hinges about y, body k's frame at its hinge, 40 links a file
MujocoFiles HingeChain(int n, bool rk4, const MujocoSettings& settings) {
  constexpr int kLinksPerFile = 40;
  const Vec3<double> inertia = RodInertia(1.0, 1.0);
  MujocoFiles files;
  for (int first = 0; first < n; first += kLinksPerFile) {
    std::ostringstream xml;
    xml.precision(17);
    xml << "<mujoco" << (first == 0 ? R"( model="hinge_chain">)" + Options(rk4, 0, settings) + "<worldbody>" : ">");
    const int end = std::min(n, first + kLinksPerFile);
    for (int k = first; k < end; ++k) {
      xml << "<body pos=\"" << (k == 0 ? 0 : 1) << R"( 0 0"><joint type="hinge" axis="0 1 0"/>)"
          << R"(<inertial pos="0.5 0 0" mass="1" diaginertia=")" << inertia.x() << " " << inertia.y() << " "
          << inertia.z() << "\"/>";
    }
    if (end < n) xml << "<include file=\"links" << end << ".xml\"/>";
    for (int k = first; k < end; ++k) xml << "</body>";
    xml << (first == 0 ? "</worldbody>" : "") << "</mujoco>";
    files.push_back({first == 0 ? "scene.xml" : "links" + std::to_string(first) + ".xml", xml.str()});
  }
  return files;
}

// humanoid_tree.h's tree: every body's frame at its joint's anchor, axes the world's
std::string Humanoid(bool rk4, const MujocoSettings& settings) {
  const std::vector<TreeBody> tree = HumanoidTree();
  std::ostringstream xml;
  xml.precision(17);
  std::function<void(int)> body = [&](int k) {
    const TreeBody& b = tree[k];
    const Vec3<double> origin = b.parent < 0 ? Vec3<double>::Zero() : tree[b.parent].anchor;
    xml << "<body name=\"" << b.name << "\" pos=\"" << Vector(b.anchor - origin) << "\">";
    const char* x = R"(<joint type="hinge" axis="1 0 0"/>)";
    const char* y = R"(<joint type="hinge" axis="0 1 0"/>)";
    const char* z = R"(<joint type="hinge" axis="0 0 1"/>)";
    switch (b.joint) {  // joints of one body in MuJoCo: the first axis fixed in the parent, the last in the body
      case TreeJoint::kFixed:
        break;
      case TreeJoint::kHingeX:
        xml << x;
        break;
      case TreeJoint::kHingeY:
        xml << y;
        break;
      case TreeJoint::kBall:
        xml << x << y << z;
        break;
      case TreeJoint::kUniversalZY:
        xml << z << y;
        break;
      case TreeJoint::kUniversalYX:
        xml << y << x;
        break;
      case TreeJoint::kUniversalXY:
        xml << x << y;
        break;
    }
    xml << "<inertial pos=\"" << Vector(b.centre - b.anchor) << "\" mass=\"" << b.mass << "\" diaginertia=\""
        << Vector(b.inertia) << "\"/>";
    for (size_t child = 0; child < tree.size(); ++child) {
      if (tree[child].parent == k) body(static_cast<int>(child));
    }
    xml << "</body>";
  };
  xml << R"(<mujoco model="humanoid_tree">)" << Options(rk4, 0, settings) << "<worldbody>";
  body(0);
  xml << "</worldbody></mujoco>";
  return xml.str();
}

int SiteId(const mjModel& model, const std::string& name) {
  const int site = mj_name2id(&model, mjOBJ_SITE, name.c_str());
  if (site < 0) throw std::logic_error("the MuJoCo scene has no site " + name);
  return site;
}

int BodyId(const mjModel& model, const std::string& name) {
  const int body = mj_name2id(&model, mjOBJ_BODY, name.c_str());
  if (body < 0) throw std::logic_error("the MuJoCo scene has no body " + name);
  return body;
}

// kMujocoHumanoidFile hanging by its torso: its free joint removed, contacts and limits off, h and the integrator
// set.
std::string HumanoidFile(bool rk4, const MujocoSettings& settings) {
  std::ifstream in(kMujocoHumanoidFile);
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const auto replace = [&xml](const std::string& from, const std::string& to) {
    const size_t at = xml.find(from);
    if (at == std::string::npos) throw std::runtime_error(std::string(kMujocoHumanoidFile) + " has no " + from);
    xml.replace(at, from.size(), to);
  };
  replace("<freejoint name=\"root\"/>", "");
  std::ostringstream option;
  option << "<option timestep=\"" << settings.step << "\" integrator=\"" << (rk4 ? "RK4" : "Euler")
         << "\"><flag contact=\"disable\" limit=\"disable\"/></option>";
  replace("<option timestep=\"0.005\"/>", option.str());
  return xml;
}

}  // namespace

MujocoFiles MujocoModel(MujocoScene scene, int n, bool rk4, const MujocoSettings& settings) {
  switch (scene) {
    case MujocoScene::kChainOfSlides:
      return {{"scene.xml", ChainOfSlides(n, rk4, settings)}};
    case MujocoScene::kChainOfFreeBodies:
      return {{"scene.xml", ChainOfFreeBodies(n, rk4, settings)}};
    case MujocoScene::kFourBar:
      return {{"scene.xml", FourBar(n, rk4, settings)}};
    case MujocoScene::kHingeChain:
      return HingeChain(n, rk4, settings);
    case MujocoScene::kHumanoid:
      return {{"scene.xml", Humanoid(rk4, settings)}};
    case MujocoScene::kHumanoidFile:
      return {{"scene.xml", HumanoidFile(rk4, settings)}};
    case MujocoScene::kRssr:
      return {{"scene.xml", SpatialFourBar(rk4, settings)}};
  }
  throw std::logic_error("unknown MuJoCo scene");
}

std::string MujocoXml(MujocoScene scene, int n, bool rk4, const MujocoSettings& settings) {
  return MujocoModel(scene, n, rk4, settings).front().second;
}

MjModelPtr LoadMujoco(const MujocoFiles& files) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  for (const auto& [name, xml] : files) {
    if (mj_makeEmptyFileVFS(&vfs, name.c_str(), static_cast<int>(xml.size())) != 0) {
      mj_deleteVFS(&vfs);
      throw std::runtime_error("MuJoCo VFS is full");
    }
    const int file = mj_findFileVFS(&vfs, name.c_str());
    std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[file]));
  }
  char error[1000] = "";
  MjModelPtr model(mj_loadXML(files.front().first.c_str(), &vfs, error, sizeof error));
  mj_deleteVFS(&vfs);
  if (!model) throw std::runtime_error(std::string("MuJoCo could not load the scene: ") + error);
  return model;
}

MjModelPtr LoadMujoco(const std::string& xml) { return LoadMujoco(MujocoFiles{{"scene.xml", xml}}); }

MjDataPtr InitialMujocoState(const mjModel& model, MujocoScene scene) {
  MjDataPtr data(mj_makeData(&model));
  if (scene == MujocoScene::kFourBar) {  // hinges: crank0, coupler0 (relative to crank0), crank1, coupler1, ...
    for (int j = 0; j < model.nv; ++j) data->qvel[j] = j % 2 == 0 ? 1.0 : -1.0;  // the couplers keep their orientation
  }
  if (scene == MujocoScene::kRssr) data->qfrc_applied[0] = RssrLinkage().drive_torque;  // the crank's hinge
  mj_forward(&model, data.get());
  return data;
}

std::string MujocoWarnings(const mjData& data) {
  static const char* const kNames[mjNWARNING] = {"near-singular inertia", "too many contacts",  "too many constraints",
                                                 "too many visual geoms", "bad number in qpos", "bad number in qvel",
                                                 "bad number in qacc",    "bad number in ctrl"};
  std::string warnings;
  for (int w = 0; w < mjNWARNING; ++w) {
    if (data.warning[w].number == 0) continue;
    warnings += (warnings.empty() ? "MuJoCo warned: " : "; ") + std::string(kNames[w]) + " (" +
                std::to_string(data.warning[w].number) + " times)";
  }
  return warnings;
}

int RunPeerBenchmarks(int argc, char** argv, void (*register_benchmarks)()) {
  mju_user_warning = [](const char*) {};
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

MujocoProbe::MujocoProbe(const mjModel& model, MujocoScene scene) : scene_(scene) {
  switch (scene) {
    case MujocoScene::kChainOfSlides:
    case MujocoScene::kChainOfFreeBodies:
      for (int i = 0; i + 1 < model.nbody; ++i) {  // body 0 is the world
        masses_.push_back(SiteId(model, "m" + std::to_string(i)));
        if (scene == MujocoScene::kChainOfFreeBodies) bases_.push_back(SiteId(model, "b" + std::to_string(i)));
      }
      return;
    case MujocoScene::kFourBar: {
      const int n = (model.nbody - 2) / 2;  // the world, n + 1 cranks and n couplers
      for (int i = 0; i < n; ++i) {
        gaps_.push_back({SiteId(model, "coupler" + std::to_string(i) + "_end"),
                         SiteId(model, "crank" + std::to_string(i + 1) + "_tip")});
      }
      for (int i = 0; i <= n; ++i) bodies_.push_back(BodyId(model, "crank" + std::to_string(i)));
      for (int i = 0; i < n; ++i) bodies_.push_back(BodyId(model, "coupler" + std::to_string(i)));
      return;
    }
    case MujocoScene::kHingeChain:
      for (int k = 1; k < model.nbody; ++k) bodies_.push_back(k);  // nested in the links' order
      return;
    case MujocoScene::kHumanoid: {
      const std::vector<TreeBody> tree = HumanoidTree();
      for (size_t k = 1; k < tree.size(); ++k) bodies_.push_back(BodyId(model, tree[k].name));
      return;
    }
    case MujocoScene::kHumanoidFile:
      for (int k = 1; k < model.nbody; ++k) bodies_.push_back(k);
      return;
    case MujocoScene::kRssr:
      gaps_.push_back({SiteId(model, "coupler_end"), SiteId(model, "rocker_tip")});
      for (const char* name : {"crank", "coupler", "rocker"}) bodies_.push_back(BodyId(model, name));
      return;
  }
}

double MujocoProbe::Violation(const mjData& data) const {
  double worst = 0.0;
  for (const auto& [a, b] : gaps_) worst = std::max(worst, (Site(data, a) - Site(data, b)).norm());
  Vec3<double> previous = Vec3<double>::Zero();  // the anchor
  for (size_t i = 0; i < masses_.size(); ++i) {
    const Vec3<double> mass = Site(data, masses_[i]);
    const double error = scene_ == MujocoScene::kChainOfSlides ? std::abs((mass - previous).norm() - 1.0)
                                                               : (Site(data, bases_[i]) - previous).norm();
    worst = std::max(worst, error);
    previous = mass;
  }
  return worst;
}

std::vector<Vec3<double>> MujocoProbe::Centres(const mjData& data) const {
  std::vector<Vec3<double>> centres;
  for (int body : bodies_) {
    const Vec3<double> p(data.xipos[3 * body], data.xipos[3 * body + 1], data.xipos[3 * body + 2]);
    centres.push_back(scene_ == MujocoScene::kFourBar ? Vec3<double>(p.x(), p.z(), 0.0) : p);
  }
  return centres;
}

}  // namespace tether::bench
