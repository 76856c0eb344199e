#include "tether/studies/gain_map.h"

#include <cmath>
#include <map>

#include "tether/tuning/gain_tuning.h"
#include "tether/tuning/stability.h"

namespace tether {
namespace {

bool IsGain(const std::string& column) {
  return column == "/stabilization/alpha" || column == "/stabilization/beta";
}

nlohmann::json BoundCurve(Integrator integrator, double h) {
  nlohmann::json curve = nlohmann::json::array();
  constexpr int kPoints = 161;
  for (int k = 0; k < kPoints; ++k) {
    const double zeta = std::pow(10.0, -4.0 + 8.0 * k / (kPoints - 1));  // 1e-4 .. 1e4
    const double omega = StabilityBound(integrator, zeta) / h;
    curve.push_back({2.0 * zeta * omega, omega * omega});
  }
  return curve;
}

}  // namespace

nlohmann::json GainMapMarks(const StudySpec& spec) {
  // one panel per distinct combination of the other columns, in row order
  std::map<std::string, bool> seen;
  nlohmann::json panels = nlohmann::json::array();
  for (int index = 0; index < RowCount(spec); ++index) {
    const std::vector<nlohmann::json> values = Combination(spec, index);
    nlohmann::json panel_values = nlohmann::json::object();
    for (size_t k = 0; k < spec.pointers.size(); ++k) {
      if (!IsGain(spec.pointers[k])) panel_values[spec.pointers[k]] = CellText(values[k]);
    }
    if (seen[panel_values.dump()]) continue;
    seen[panel_values.dump()] = true;

    const Model<double> model = SceneOfRow(spec, values, "row " + std::to_string(index)).model;
    const Integrator integrator = model.simulation.integrator;
    const double h = model.simulation.step;
    nlohmann::json marks = nlohmann::json::array();
    for (const NamedGains& preset : GainPresets(integrator, h)) {
      if (preset.beta > 0.0) marks.push_back({{"name", preset.name}, {"alpha", preset.alpha}, {"beta", preset.beta}});
    }
    const TuneResult tuned = TuneGains(model, TuneSettings{});
    marks.push_back({{"name", "tuned"}, {"alpha", tuned.alpha}, {"beta", tuned.beta}});
    panels.push_back({{"values", panel_values}, {"step", h}, {"bound", BoundCurve(integrator, h)}, {"marks", marks}});
  }
  return {{"panels", panels}};
}

}  // namespace tether
