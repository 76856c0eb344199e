#include "tether/dynamics/constraints/constraint_rows_impl.h"

namespace tether {

#define TETHER_INSTANTIATE_CONSTRAINT_ROWS(T)                                                                        \
  template ConstraintSet<T> BuildConstraintSet<T>(const Model<T>&, const VecX<T>&);                                  \
  template std::vector<RowInfo> DescribeRows<T>(const Model<T>&, const ConstraintSet<T>&);                           \
  template void EvaluateConstraintRows<T>(const Model<T>&, const ConstraintSet<T>&, const BodyFrames<T>&,            \
                                          const VecX<T>&, const VecX<T>&, bool, std::vector<ConstraintRow<T>>*);     \
  template void EvaluateLimitRow<T>(const Model<T>&, const LimitPrimitive<T>&, const BodyFrames<T>&, const VecX<T>&, \
                                    const VecX<T>&, bool, ConstraintRow<T>*);                                        \
  template Violation LargestViolation<T>(const std::vector<RowInfo>&, const std::vector<ConstraintRow<T>>&);         \
  template void AxisNormals<T>(int, const Vec3<T>&, Vec3<T>*, Vec3<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_CONSTRAINT_ROWS)

}  // namespace tether
