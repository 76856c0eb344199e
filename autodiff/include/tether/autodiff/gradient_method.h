// Which method computes a loss gradient, and what `auto` chooses.
//
//   jet      forward mode (residuals.h): ceil(P / kJetStride) Jet runs, about one plain run per parameter;
//   adjoint  reverse mode (adjoint.h): one double run and one recorded replay, a constant multiple of a plain
//            run whatever P;
//   fd       central differences: 1 + 2P plain runs (a check, never chosen by auto);
//   auto     Jets below kAdjointCrossover parameters, the adjoint from there on: the P at which the adjoint
//            became the cheaper of the two on the gradient-cost benchmark (bench/gradient_cost.py prints it).
#pragma once

#include <string>

#include "tether/autodiff/adjoint.h"

namespace tether {

enum class GradientMethod { kAuto, kJet, kAdjoint, kCentral };

inline constexpr int kAdjointCrossover = 5;

// "auto", "jet", "adjoint" or "fd"; throws InputError naming `where` (a flag, a keyword argument) otherwise.
GradientMethod ParseGradientMethod(const std::string& text, const std::string& where);
std::string GradientMethodName(GradientMethod method);

// The method `method` stands for with `parameters` parameters (auto resolved; the others as they are).
GradientMethod ResolveGradientMethod(GradientMethod method, int parameters);

// The loss against the observations and its gradient by `method` (auto resolved); *adjoint, when given, gets
// what the adjoint kept if it ran.
LossGradient LossGradientBy(GradientMethod method, const Model<double>& model, const ParameterSet& parameters,
                            const Observations& observations, AdjointReport* adjoint = nullptr);

// What `tether gradient` prints (and the Python module's gradient returns): {"loss", "gradient": {PTR: g},
// "parameters": {PTR: value}, "method", "seconds"}, and "adjoint": {"steps", "interval", "checkpoints",
// "memory_bytes"} when the adjoint computed it.
nlohmann::json GradientJson(const ParameterSet& parameters, const Model<double>& model, const LossGradient& result,
                            GradientMethod method, double seconds, const AdjointReport& adjoint = {});

}  // namespace tether
