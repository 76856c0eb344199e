// A loss's gradient three ways, each held to the next: Jets against central differences (relative
// `central_tolerance`), the adjoint against the Jets (relative 1e-9), every component nonzero (the parameter
// matters). Returns the Jets'.
#pragma once

#include <gtest/gtest.h>

#include <cmath>

#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"

namespace tether::testing {

inline LossGradient ExpectGradientsAgree(const Model<double>& model, const ParameterSet& parameters,
                                         const Observations& observations, double central_tolerance = 1e-6) {
  const LossGradient jets = JetLossGradient(model, parameters, observations);
  const LossGradient adjoint = AdjointLossGradient(model, parameters, observations);
  const LossGradient differences = CentralDifferenceLossGradient(model, parameters, observations);
  for (int i = 0; i < parameters.size(); ++i) {
    const std::string& pointer = parameters.pointers()[i];
    EXPECT_NE(jets.gradient[i], 0.0) << pointer;
    EXPECT_NEAR(jets.gradient[i], differences.gradient[i], central_tolerance * std::abs(differences.gradient[i]))
        << pointer;
    EXPECT_NEAR(adjoint.gradient[i], jets.gradient[i], 1e-9 * std::abs(jets.gradient[i])) << pointer;
  }
  return jets;
}

}  // namespace tether::testing
