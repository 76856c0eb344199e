#include "test_scenes.h"

#include <cmath>
#include <sstream>

#include "tether/dynamics/io/trajectory_csv.h"

namespace tether::testing {

Model<double> SceneFromJson(const std::string& json_text) {
  return ParseScene(ParseJsonText(json_text, "inline.json"), "inline.json").model;
}

Recording Record(const Model<double>& model, int every) {
  RunOptions options;
  options.every = every;
  return tether::Record(model, options);
}

std::string TrajectoryCsvAt(const Model<double>& model, const std::vector<double>& times) {
  std::ostringstream csv;
  TrajectoryCsvWriter writer(model, &csv);
  RunOptions run;
  run.every = 1 << 30;
  run.stops = times;
  Simulate<double>(model, run, [&writer](const Sample<double>& s) {
    if (s.stop >= 0) writer.Write(s);
  });
  return csv.str();
}

Model<double> Pendulum60(const std::string& integrator, double step, double duration) {
  const double length = 0.7, angle = M_PI / 3;
  const std::string x = std::to_string(length * std::sin(angle)), y = std::to_string(-length * std::cos(angle));
  Model<double> model = SceneFromJson(R"({
    "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [)" + x + ", " + y + R"(]}],
    "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})");
  model.simulation.integrator = integrator == "euler"              ? Integrator::kEuler
                                : integrator == "symplectic_euler" ? Integrator::kSymplecticEuler
                                : integrator == "rk45"             ? Integrator::kRk45
                                                                   : Integrator::kRk4;
  model.simulation.step = step;
  model.simulation.duration = duration;
  return model;
}

double EllipticK(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 40 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double mean = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = mean;
  }
  return M_PI / (2.0 * a);
}

namespace {

void CollectNumberPointers(const nlohmann::json& node, const std::string& at, std::vector<std::string>* out) {
  if (node.is_number()) out->push_back(at);
  if (node.is_array()) {
    for (size_t k = 0; k < node.size(); ++k) CollectNumberPointers(node[k], at + "/" + std::to_string(k), out);
  }
  if (node.is_object()) {
    for (auto it = node.begin(); it != node.end(); ++it) CollectNumberPointers(it.value(), at + "/" + it.key(), out);
  }
}

}  // namespace

std::vector<std::string> NumberPointers(const nlohmann::json& document) {
  std::vector<std::string> pointers;
  CollectNumberPointers(document, "", &pointers);
  return pointers;
}

}  // namespace tether::testing
