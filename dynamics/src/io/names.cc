#include "tether/dynamics/io/names.h"

#include <utility>
#include <vector>

#include "tether/dynamics/integration/integrator_descriptor.h"
#include "tether/dynamics/model/errors.h"

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
  std::vector<std::pair<const char*, Integrator>> table;
  for (const IntegratorDescriptor& d : kIntegrators) table.emplace_back(d.name, d.integrator);
  return Lookup<Integrator>(table, name, where, "integrator");
}

KktSolver ParseKktSolver(const std::string& name, const std::string& where) {
  return Lookup<KktSolver>({{"auto", KktSolver::kAuto}, {"dense", KktSolver::kDense}, {"sparse", KktSolver::kSparse}},
                           name, where, "solver");
}

Stabilization ParseStabilization(const std::string& name, const std::string& where) {
  return Lookup<Stabilization>({{"none", Stabilization::kNone},
                                {"baumgarte", Stabilization::kBaumgarte},
                                {"projection", Stabilization::kProjection}},
                               name, where, "stabilization method");
}

}  // namespace tether
