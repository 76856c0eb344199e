// Simulates a pendulum for one second through the installed library and checks that it stays on its rod.
#include <cmath>
#include <cstdio>

#include "tether/dynamics/scene_reader.h"
#include "tether/dynamics/simulator.h"

int main() {
  const tether::Scene scene = tether::ParseScene(nlohmann::json::parse(R"({
    "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
    "constraints": [{"type": "distance", "bodies": ["world", "bob"]}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}]})"), "consumer.json");
  double worst = 0.0;
  tether::Simulate<double>(scene.model, {}, [&worst](const tether::Sample<double>& s) {
    worst = std::fmax(worst, s.constraint_error);
  });
  std::printf("largest constraint error %g\n", worst);
  return worst < 1e-6 ? 0 : 1;
}
