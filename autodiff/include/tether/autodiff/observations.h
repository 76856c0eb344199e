// Observations: a trajectory CSV (CONTRACT.md) with a `t` column and any subset of the trajectory's columns,
// at any times within the simulated interval, in any row order; an empty cell is a missing value. Coordinates,
// velocities and `energy` can be observed; `constraint_error` is a diagnostic and cannot.
// Every error names the file and the line (or the column).
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/model.h"

namespace tether {

struct ObservedColumn {
  enum class Source { kCoordinate, kVelocity, kEnergy };
  std::string name;  // as in the CSV header
  Source source = Source::kCoordinate;
  int index = 0;     // into q or v
};

struct Observations {
  std::string path;
  std::vector<ObservedColumn> columns;
  std::vector<double> times;               // strictly increasing
  std::vector<std::vector<double>> values;  // values[row][column]; NaN where the cell is empty
  std::vector<int> lines;                  // the file line of each row, for messages

  // Number of observed (non-empty) cells.
  int CellCount() const;
};

// Reads and validates OBS.csv against a model (its bodies, its duration). Throws InputError.
Observations ReadObservations(const std::string& path, const Model<double>& model);

}  // namespace tether
