// The trajectory CSV of docs/contract.md: a header row, then one row per output state with the columns of
// trajectory_columns.h, every number printed in the shortest form that reads back as the same double (std::to_chars):
// full double precision without noise digits (0.1, not 0.10000000000000001).
#pragma once

#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/io/trajectory_columns.h"

namespace tether {

class TrajectoryCsvWriter {
 public:
  // Writes the header row.
  TrajectoryCsvWriter(const Model<double>& model, std::ostream* out);
  void Write(const Sample<double>& sample);

 private:
  const Model<double>& model_;
  std::vector<TrajectoryColumn> columns_;
  std::ostream* out_;
  std::string line_;
};

// The events CSV of `tether simulate --events`: the header t,kind,constraint,speed_before,speed_after, then a row
// per event, numbers as above, a name holding a comma, quote or line break quoted.
void WriteEventsCsv(const std::vector<RunEvent>& events, std::ostream* out);

}  // namespace tether
