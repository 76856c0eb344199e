// Residuals against observations, their Jacobian with respect to parameters, and the loss gradient.
//
//   r = simulated - observed at every observed cell (rows in time order, columns in file order),
//   loss = 1/2 |r|^2,  d loss / dp = J^T r,  J = dr/dp.
// The run steps exactly onto every observation time (RunOptions::stops), so no interpolation enters.
//
// J is computed forward with Jets: the parameters are taken kJetStride at a time, each chunk seeding one
// derivative direction per parameter in a Model<Jet> and simulating it once; any number of parameters works,
// at ceil(P / kJetStride) Jet runs. Inside each run every KKT solve applies the implicit function theorem
// (schur_solver.h). The central-difference gradient uses steps h_i = 1e-5 max(|p_i|, 1e-2) (relative for
// ordinary values, absolute near zero), balancing truncation (h^2) against rounding (eps / h).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/dynamics/integration/simulator.h"

namespace tether {

// r(model) for a model of any scalar; throws SimulationDiverged if the run diverges.
template <typename T>
VecX<T> ObservationResiduals(const Model<T>& model, const Observations& observations,
                             const RunOptions& options = {});

// Values and Jacobian (rows x parameters) of any residual function of a model, by chunks of Jets.
using JetResidualFunction = std::function<VecX<Jet>(const Model<Jet>&)>;
void EvaluateByJets(const Model<double>& model, const ParameterSet& parameters, const JetResidualFunction& residuals,
                    Eigen::VectorXd* values, Eigen::MatrixXd* jacobian);

struct LossGradient {
  double loss = 0.0;
  std::vector<double> gradient;  // one per parameter
};

// Jets with the implicit-function KKT solve (factor_jet_matrices: the Jet-factorization oracle instead).
LossGradient JetLossGradient(const Model<double>& model, const ParameterSet& parameters,
                             const Observations& observations, bool factor_jet_matrices = false);
// Central differences, two double runs per parameter.
LossGradient CentralDifferenceLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                           const Observations& observations);
double CentralDifferenceStep(double value);

}  // namespace tether
