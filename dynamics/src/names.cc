#include "tether/dynamics/names.h"

#include <utility>
#include <vector>

#include "tether/dynamics/errors.h"

namespace tether {
namespace {

template <typename E>
E Lookup(const std::vector<std::pair<const char*, E>>& table, const std::string& name, const std::string& where,
         const char* kind) {
  std::string expected;
  for (size_t i = 0; i < table.size(); ++i) {
    if (name == table[i].first) return table[i].second;
    expected += i == 0 ? "" : (i + 1 == table.size() ? " or " : ", ");
    expected += table[i].first;
  }
  throw InputError(where + ": unknown " + kind + " '" + name + "' (expected " + expected + ")");
}

}  // namespace

Integrator ParseIntegrator(const std::string& name, const std::string& where) {
  return Lookup<Integrator>({{"euler", Integrator::kEuler},
                             {"symplectic_euler", Integrator::kSymplecticEuler},
                             {"rk4", Integrator::kRk4},
                             {"rk45", Integrator::kRk45}},
                            name, where, "integrator");
}

KktSolver ParseKktSolver(const std::string& name, const std::string& where) {
  return Lookup<KktSolver>({{"auto", KktSolver::kAuto}, {"dense", KktSolver::kDense}, {"sparse", KktSolver::kSparse}},
                           name, where, "solver");
}

Stabilization ParseStabilization(const std::string& name, const std::string& where) {
  return Lookup<Stabilization>(
      {{"none", Stabilization::kNone}, {"baumgarte", Stabilization::kBaumgarte}, {"projection", Stabilization::kProjection}},
      name, where, "stabilization method");
}

}  // namespace tether
