#include "tether/dynamics/effects/effects_impl.h"

namespace tether {

#define TETHER_INSTANTIATE_EFFECTS(T)                                                                         \
  template Mat3<T> PrincipalInertia<T>(const Mat3<T>&, const Vec4<double>&);                                  \
  template std::vector<Mat3<T>> PrincipalInertias<T>(const Model<T>&);                                        \
  template void AccumulateForces<T>(const Model<T>&, const JointCoordinates<T>&, const std::vector<Mat3<T>>&, \
                                    const BodyFrames<T>&, double, const VecX<T>&, const VecX<T>&, VecX<T>*);  \
  template T KineticEnergy<T>(const Model<T>&, const VecX<T>&);                                               \
  template T Energy<T>(const Model<T>&, const JointCoordinates<T>&, const BodyFrames<T>&, const VecX<T>&,     \
                       const VecX<T>&);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_EFFECTS)

}  // namespace tether
