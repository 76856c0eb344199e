// Observations: a trajectory CSV (docs/contract.md) with a `t` column and any subset of the trajectory's columns
// (trajectory_columns.h), at any times within the simulated interval, in any row order; an empty cell is a
// missing value. Coordinates, quaternion components, velocities, joint coordinates (encoders), markers and
// `energy` can be observed; `constraint_error` is a diagnostic and cannot. q and -q are one rotation: a recorded
// quaternion is compared with the simulated one after taking the sign that agrees with it (the sign of the dot
// product over its recorded components, row by row), so a recording with sign flips fits as well as one without.
// Every error names the file and the line (or the column).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tether/dynamics/io/trajectory_columns.h"

namespace tether {

struct Observations {
  std::string path;
  std::vector<TrajectoryColumn> columns;
  std::vector<double> times;               // strictly increasing
  std::vector<std::vector<double>> values;  // values[row][column]; NaN where the cell is empty
  std::vector<int> lines;                  // the file line of each row, for messages

  // Number of observed (non-empty) cells.
  int CellCount() const;
};

// Reads and validates OBS.csv against a model (its bodies, its duration). Throws InputError, also for a file
// larger than kMaxDataBytes, refused before reading (tether holds every cell in memory).
inline constexpr std::uintmax_t kMaxDataBytes = std::uintmax_t{1} << 30;  // 1 GiB
Observations ReadObservations(const std::string& path, const Model<double>& model);
// The same for a whole trajectory CSV as `tether simulate` writes it: its constraint_error column is left out.
Observations ReadTrajectory(const std::string& path, const Model<double>& model);

// The same from columns in memory (the Python module's data): `names` (one of them "t") and rows of numbers, NaN
// where a value is missing; validated as a file is, messages naming `source` and the row (from 1).
Observations MakeObservations(const std::string& source, const std::vector<std::string>& names,
                              const std::vector<std::vector<double>>& rows, const Model<double>& model);

// Whether the observations have an energy column (RunOptions::energy).
bool ObservesEnergy(const Observations& observations);

// Calls add(c, simulated - observed) for every observed cell c of row `row`, in column order, the simulated
// value taken from a sample of a run of `model` at that row's time.
template <typename T, typename Add>
void ObservedResiduals(const Model<T>& model, const Observations& observations, size_t row, const Sample<T>& sample,
                       Add add) {
  const std::vector<double>& observed = observations.values[row];
  const std::vector<TrajectoryColumn>& columns = observations.columns;
  for (size_t c = 0; c < columns.size(); ++c) {
    if (std::isnan(observed[c])) continue;
    const T simulated = ColumnValue(model, columns[c], sample);
    double sign = 1.0;
    if (columns[c].body != kWorld) {  // a quaternion component: the sign of the recorded quaternion
      double dot = 0.0;
      for (size_t k = 0; k < columns.size(); ++k) {
        if (columns[k].body == columns[c].body && !std::isnan(observed[k])) {
          dot += observed[k] * Value(ColumnValue(model, columns[k], sample));
        }
      }
      if (dot < 0.0) sign = -1.0;
    }
    add(c, simulated - T(sign * observed[c]));
  }
}

}  // namespace tether
