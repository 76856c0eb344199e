// How derivatives enter a run, written once for every caller (the residuals' Jacobian, the shooting problem, the
// gain tuner's objective, the adjoint).
//
// Forward mode: a Jet's derivative part v holds dx/du_k for up to kJetStride unknowns u_k of one run; a field
// seeded for unknown k has v[k] = dx/du_k (1 where the unknown is the field itself, x where it is log x, the
// chain rule's factor where the unknown is something the field is a function of, as the tuner's (log omega,
// zeta) are of alpha and beta). Reverse mode: a field becomes a variable of the tape (reverse.h), whose adjoint
// the backward sweep accumulates.
#pragma once

#include <vector>

#include "tether/dynamics/model/model_field.h"
#include "tether/dynamics/scalars/reverse.h"

namespace tether {

// One model field's derivative with respect to unknown `direction` of a Jet run.
struct JetSeed {
  ModelField field;
  int direction = 0;        // 0 <= direction < kJetStride
  double derivative = 1.0;  // d field / d unknown
};

// `value` as a Jet whose derivative direction `direction` is `derivative` (a constant where direction < 0).
Jet SeededJet(double value, int direction, double derivative = 1.0);

// The model in Jets, each seed's field carrying its derivative (seeds of one field in several directions add up).
Model<Jet> SeededModel(const Model<double>& model, const std::vector<JetSeed>& seeds);

// The model in Revs with each of `fields` a new variable of the tape, in order; the variables in `variables`.
Model<Rev> RecordedModel(const Model<double>& model, const std::vector<ModelField>& fields, Tape* tape,
                         std::vector<Rev>* variables);

}  // namespace tether
