#include "mujoco_models.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tether::bench {
namespace {

constexpr const char* kOptions =
    R"(<option timestep="0.001" gravity="0 0 -9.81" solver="Newton" iterations="100" tolerance="1e-8" )"
    R"(integrator="%s"><flag energy="enable"/></option>)"
    R"(<default><equality solref="0.02 1" solimp="0.9 0.95 0.001"/></default>)";

std::string Options(bool rk4) {
  std::string options = kOptions;
  options.replace(options.find("%s"), 2, rk4 ? "RK4" : "Euler");
  return options;
}

std::string Chain(int n, bool rk4) {
  std::ostringstream xml;
  xml << R"(<mujoco model="chain">)" << Options(rk4) << R"(<worldbody><site name="anchor"/>)";
  for (int i = 0; i < n; ++i) {
    xml << "<body name=\"p" << i << "\" pos=\"" << i + 1 << " 0 0\">"
        << R"(<joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/><joint type="slide" axis="0 0 1"/>)"
        << R"(<inertial pos="0 0 0" mass="1" diaginertia="1e-6 1e-6 1e-6"/>)"
        << "<site name=\"s" << i << "\"/></body>";
  }
  xml << "</worldbody><tendon>";
  for (int i = 0; i < n; ++i) {
    xml << "<spatial name=\"t" << i << "\"><site site=\"" << (i == 0 ? std::string("anchor") : "s" + std::to_string(i - 1))
        << "\"/><site site=\"s" << i << "\"/></spatial>";
  }
  xml << "</tendon><equality>";
  for (int i = 0; i < n; ++i) xml << "<tendon tendon1=\"t" << i << "\"/>";
  xml << "</equality></mujoco>";
  return xml.str();
}

std::string FourBar(bool rk4) {
  return std::string(R"(<mujoco model="four_bar">)") + Options(rk4) +
         R"(<worldbody>
  <body name="crank0"><joint type="hinge" axis="0 1 0"/>
    <inertial pos="0 0 0.5" mass="1" diaginertia="0.0833333333333333 0.0833333333333333 1e-6"/>
    <body name="coupler" pos="0 0 1"><joint type="hinge" axis="0 1 0"/>
      <inertial pos="0.5 0 0" mass="1" diaginertia="1e-6 0.0833333333333333 0.0833333333333333"/>
      <site name="coupler_end" pos="1 0 0"/>
    </body>
  </body>
  <body name="crank1" pos="1 0 0"><joint type="hinge" axis="0 1 0"/>
    <inertial pos="0 0 0.5" mass="1" diaginertia="0.0833333333333333 0.0833333333333333 1e-6"/>
    <site name="crank1_tip" pos="0 0 1"/>
  </body>
</worldbody>
<equality><connect body1="coupler" body2="crank1" anchor="1 0 0"/></equality></mujoco>)";
}

}  // namespace

std::string MujocoScene(PeerScene scene, int n, bool rk4) { return scene == PeerScene::kChain ? Chain(n, rk4) : FourBar(rk4); }

MjModelPtr LoadMujoco(const std::string& xml) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const char* name = "scene.xml";
  if (mj_makeEmptyFileVFS(&vfs, name, static_cast<int>(xml.size())) != 0) throw std::runtime_error("MuJoCo VFS is full");
  const int file = mj_findFileVFS(&vfs, name);
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[file]));
  char error[1000] = "";
  MjModelPtr model(mj_loadXML(name, &vfs, error, sizeof error));
  mj_deleteVFS(&vfs);
  if (!model) throw std::runtime_error(std::string("MuJoCo could not load the scene: ") + error);
  return model;
}

MjDataPtr InitialMujocoState(const mjModel& model, PeerScene scene) {
  MjDataPtr data(mj_makeData(&model));
  if (scene == PeerScene::kFourBar) {  // hinges: crank0, coupler (relative to crank0), crank1
    data->qvel[0] = 1.0;
    data->qvel[1] = -1.0;  // the coupler keeps its orientation
    data->qvel[2] = 1.0;
  }
  mj_forward(&model, data.get());
  return data;
}

double MujocoViolation(const mjModel& model, const mjData& data, PeerScene scene) {
  if (scene == PeerScene::kFourBar) {
    const mjtNum* a = data.site_xpos + 3 * mj_name2id(&model, mjOBJ_SITE, "coupler_end");
    const mjtNum* b = data.site_xpos + 3 * mj_name2id(&model, mjOBJ_SITE, "crank1_tip");
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
  }
  double worst = 0.0;
  for (int body = 1; body < model.nbody; ++body) {  // body 0 is the world, at the origin like the anchor
    const mjtNum* p = data.xpos + 3 * body;
    const mjtNum* q = data.xpos + 3 * (body - 1);
    const double length = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    worst = std::max(worst, std::abs(length - 1.0));
  }
  return worst;
}

}  // namespace tether::bench
