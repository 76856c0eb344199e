// The names that scene files and the command line use for integrators, KKT solver paths and stabilization
// methods (docs/contract.md), in one place. A name that is not known throws InputError
// "<where>: unknown <kind> '<name>' (expected ...)", where `where` names the JSON Pointer or the flag.
#pragma once

#include <string>

#include "tether/dynamics/model/model.h"

namespace tether {

Integrator ParseIntegrator(const std::string& name, const std::string& where);
KktSolver ParseKktSolver(const std::string& name, const std::string& where);
Stabilization ParseStabilization(const std::string& name, const std::string& where);

}  // namespace tether
