// Through the installed libraries: simulates a pendulum for one second (it must stay on its rod), then
// differentiates its final height with respect to the rod length, by Jets and by central differences.
#include <cmath>
#include <cstdio>

#include "tether/autodiff/residuals.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"

int main() {
  const tether::Scene scene = tether::ParseScene(nlohmann::json::parse(R"({
    "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
    "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 1.0}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}]})"), "consumer.json");
  double worst = 0.0;
  tether::Simulate<double>(scene.model, {}, [&worst](const tether::Sample<double>& s) {
    worst = std::fmax(worst, s.constraint_error);
  });
  tether::Observations observed;
  observed.columns = {{"bob.y", tether::TrajectoryColumn::Kind::kConfiguration, 1}};
  observed.times = {1.0};
  observed.values = {{0.0}};
  observed.lines = {2};
  const tether::ParameterSet length(scene, {"/constraints/0/length"});
  const double jet = tether::JetLossGradient(scene.model, length, observed).gradient[0];
  const double fd = tether::CentralDifferenceLossGradient(scene.model, length, observed).gradient[0];
  std::printf("largest constraint error %g, d loss / d length: jet %.10g, central differences %.10g\n", worst, jet, fd);
  return worst < 1e-6 && std::abs(jet - fd) <= 1e-6 * std::fmax(1.0, std::abs(fd)) ? 0 : 1;
}
