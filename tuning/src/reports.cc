#include "tether/tuning/reports.h"

#include <cmath>

namespace tether {
namespace {

nlohmann::json NumberOrNull(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json MetricsJson(const GainMetrics& m) {
  nlohmann::json j = {{"name", m.name},
                      {"alpha", m.alpha},
                      {"beta", m.beta},
                      {"objective", m.objective},
                      {"diverged", m.diverged},
                      {"rms_position_error", m.rms_position_error},
                      {"max_constraint_error", m.max_constraint_error},
                      {"energy_drift", m.energy_drift},
                      {"seconds", m.seconds}};
  if (m.diverged) j["divergence"] = m.divergence;
  return j;  // NaN (no reference, or diverged) prints as null
}

}  // namespace

nlohmann::json TuneJson(const TuneResult& result, const std::string& objective_kind, const std::string& optimizer,
                        double step) {
  nlohmann::json json = {{"alpha", result.alpha},
                         {"beta", result.beta},
                         {"omega", result.omega},
                         {"zeta", result.zeta},
                         {"objective", result.objective},
                         {"objective_kind", objective_kind},
                         {"window", result.window},
                         {"optimizer", optimizer},
                         {"evaluations", result.optimizer.evaluations},
                         {"seconds", result.optimizer.seconds},
                         {"optimizer_message", result.optimizer.message},
                         {"stability", {{"h_omega", step * result.omega},
                                        {"bound", result.bound},
                                        {"margin", result.margin},
                                        {"omega_upper", result.omega_upper}}}};
  json["comparison"] = nlohmann::json::array();
  for (const GainMetrics& m : result.comparison) json["comparison"].push_back(MetricsJson(m));
  return json;
}

nlohmann::json IdentifyJson(const ParameterSet& parameters, const IdentifyResult& r, const std::string& optimizer) {
  nlohmann::json j;
  j["parameters"] = nlohmann::json::object();
  j["standard_deviation"] = nlohmann::json::object();
  j["initial_parameters"] = nlohmann::json::object();
  j["correlation"] = nlohmann::json::object();
  for (int i = 0; i < parameters.size(); ++i) {
    const std::string& ptr = parameters.pointers()[i];
    j["parameters"][ptr] = r.estimate[i];
    j["standard_deviation"][ptr] = NumberOrNull(r.standard_deviation[i]);
    j["initial_parameters"][ptr] = r.initial[i];
    for (int k = 0; k < parameters.size(); ++k) {
      j["correlation"][ptr][parameters.pointers()[k]] = NumberOrNull(r.correlation(i, k));
    }
  }
  j["initial_cost"] = r.initial_cost;
  j["final_cost"] = r.final_cost;
  j["condition_number"] = NumberOrNull(r.condition_number);
  j["residual_count"] = r.residual_count;
  j["evaluations"] = r.optimizer.evaluations;
  j["seconds"] = r.optimizer.seconds;
  j["optimizer"] = optimizer;
  j["optimizer_message"] = r.optimizer.message;
  j["gradient_method"] = r.gradient_method;
  j["segments"] = r.segments;
  j["stopping_reason"] = r.stopping_reason;
  j["warnings"] = r.warnings;
  j["failed"] = r.failed;
  if (r.starts > 1 || !r.constraints.empty()) {  // trajectory optimisation (trajectory_fit.h)
    j["feasible"] = r.feasible;
    j["starts"] = {{"count", r.starts}, {"feasible", r.feasible_starts}, {"best", r.best_start}};
    j["constraints"] = nlohmann::json::array();
    for (const IdentifyResult::Constraint& c : r.constraints) {
      nlohmann::json entry = {{"column", c.target.column},
                              {c.target.at_least ? "at_least" : "at_most", c.target.value},
                              {"t", c.target.time},
                              {"simulated", c.simulated},
                              {"met", c.met}};
      if (c.target.from < c.target.time) {  // over an interval: simulated at its step closest to the bound
        entry["from"] = c.target.from;
        entry["at"] = c.at;
      }
      j["constraints"].push_back(entry);
    }
  }
  j["residuals"] = nlohmann::json::array();
  for (const ResidualStatistics& s : r.residuals) {
    j["residuals"].push_back({{"file", s.file}, {"column", s.column}, {"count", s.count}, {"rms", s.rms},
                              {"max", s.largest}});
  }
  return j;
}

}  // namespace tether
