#include "tether/autodiff/seeds.h"

namespace tether {

Jet SeededJet(double value, int direction, double derivative) {
  Jet x(value);
  if (direction >= 0) x.v[direction] = derivative;
  return x;
}

Model<Jet> SeededModel(const Model<double>& model, const std::vector<JetSeed>& seeds) {
  Model<Jet> out = CastModel<Jet>(model);
  for (const JetSeed& seed : seeds) seed.field(out).v[seed.direction] += seed.derivative;
  return out;
}

Model<Rev> RecordedModel(const Model<double>& model, const std::vector<ModelField>& fields, Tape* tape,
                         std::vector<Rev>* variables) {
  Model<Rev> out = CastModel<Rev>(model);
  variables->clear();
  for (const ModelField& field : fields) {
    Rev& x = field(out);
    x = tape->Variable(x.a);
    variables->push_back(x);
  }
  return out;
}

}  // namespace tether
