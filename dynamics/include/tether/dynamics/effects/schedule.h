// Piecewise linear schedules: s(t) = v_k + (t - t_k) / (t_{k+1} - t_k) (v_{k+1} - v_k) on [t_k, t_{k+1}],
// held at v_0 before t_0 and at v_last after t_last. Times are data (double); values may carry derivatives.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

// Through (times[k], values[k]); empty means "not scheduled".
template <typename V>
struct Schedule {
  std::vector<double> times;
  std::vector<V> values;
  bool empty() const { return times.empty(); }

  // The same schedule with values of scalar U (V a scalar or an Eigen vector of one).
  template <typename U>
  auto Cast() const {
    if constexpr (std::is_arithmetic_v<V>) {
      Schedule<U> out{times, {}};
      for (const V& v : values) out.values.push_back(U(v));
      return out;
    } else {
      Schedule<Vec3<U>> out{times, {}};
      for (const V& v : values) out.values.push_back(v.template cast<U>());
      return out;
    }
  }
};

template <typename V>
V ScheduleValue(const Schedule<V>& schedule, double t) {
  const std::vector<double>& times = schedule.times;
  if (t <= times.front()) return schedule.values.front();
  if (t >= times.back()) return schedule.values.back();
  const size_t k = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const double w = (t - times[k]) / (times[k + 1] - times[k]);
  return schedule.values[k] + (schedule.values[k + 1] - schedule.values[k]) * w;
}

}  // namespace tether
