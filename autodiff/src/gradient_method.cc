#include "tether/autodiff/gradient_method.h"

#include "tether/dynamics/model/errors.h"

namespace tether {

GradientMethod ParseGradientMethod(const std::string& text, const std::string& where) {
  if (text == "auto") return GradientMethod::kAuto;
  if (text == "jet") return GradientMethod::kJet;
  if (text == "adjoint") return GradientMethod::kAdjoint;
  if (text == "fd") return GradientMethod::kCentral;
  throw InputError(where + ": unknown method '" + text + "' (expected auto, adjoint, jet or fd)");
}

std::string GradientMethodName(GradientMethod method) {
  switch (method) {
    case GradientMethod::kAuto:
      return "auto";
    case GradientMethod::kJet:
      return "jet";
    case GradientMethod::kAdjoint:
      return "adjoint";
    case GradientMethod::kCentral:
      return "fd";
  }
  return "auto";
}

GradientMethod ResolveGradientMethod(GradientMethod method, int parameters) {
  if (method != GradientMethod::kAuto) return method;
  return parameters >= kAdjointCrossover ? GradientMethod::kAdjoint : GradientMethod::kJet;
}

LossGradient LossGradientBy(GradientMethod method, const Model<double>& model, const ParameterSet& parameters,
                            const Observations& observations, AdjointReport* adjoint) {
  switch (ResolveGradientMethod(method, parameters.size())) {
    case GradientMethod::kAdjoint:
      return AdjointLossGradient(model, parameters, observations, 0, adjoint);
    case GradientMethod::kCentral:
      return CentralDifferenceLossGradient(model, parameters, observations);
    default:
      return JetLossGradient(model, parameters, observations);
  }
}

nlohmann::json GradientJson(const ParameterSet& parameters, const Model<double>& model, const LossGradient& result,
                            GradientMethod method, double seconds, const AdjointReport& adjoint) {
  nlohmann::json out;
  out["loss"] = result.loss;
  out["gradient"] = nlohmann::json::object();
  out["parameters"] = nlohmann::json::object();
  const std::vector<double> values = parameters.Values(model);
  for (int i = 0; i < parameters.size(); ++i) {
    out["gradient"][parameters.pointers()[i]] = result.gradient[i];
    out["parameters"][parameters.pointers()[i]] = values[i];
  }
  out["method"] = GradientMethodName(method);
  if (method == GradientMethod::kAdjoint) {
    out["adjoint"] = {{"steps", adjoint.steps},
                      {"interval", adjoint.interval},
                      {"checkpoints", adjoint.checkpoints},
                      {"memory_bytes", adjoint.memory_bytes}};
  }
  out["seconds"] = seconds;
  return out;
}

}  // namespace tether
