#include "scene_overrides.h"

namespace tether::cli {

void SceneOverrides::Register(CLI::App* app, bool gains) {
  app->add_option("--duration", duration, "simulated time, s (overrides /simulation/duration)");
  app->add_option("--step", step, "time step h, s (overrides /simulation/step)");
  app->add_option("--integrator", integrator, "euler, symplectic_euler, rk4 or rk45");
  app->add_option("--solver", solver, "KKT solver path: auto, dense or sparse");
  if (!gains) return;
  app->add_option("--alpha", alpha, "Baumgarte alpha, 1/s (selects the baumgarte method)");
  app->add_option("--beta", beta, "Baumgarte beta, 1/s^2 (selects the baumgarte method)");
  app->add_option("--stabilization", stabilization, "none, baumgarte or projection");
}

}  // namespace tether::cli
