#include "tether/dynamics/trajectory_csv.h"

#include <charconv>

#include "tether/dynamics/errors.h"

namespace tether {

TrajectoryCsvWriter::TrajectoryCsvWriter(const Model<double>& model, std::ostream* out)
    : model_(model), columns_(TrajectoryColumns(model)), out_(out) {
  for (size_t i = 0; i < columns_.size(); ++i) *out_ << (i ? "," : "") << columns_[i].name;
  *out_ << '\n';
}

void TrajectoryCsvWriter::Write(const Sample<double>& s) {
  char number[32];
  line_.clear();
  auto put = [&](double x) {
    const std::to_chars_result end = std::to_chars(number, number + sizeof number, x);
    if (!line_.empty()) line_ += ',';
    line_.append(number, end.ptr);
  };
  for (const TrajectoryColumn& column : columns_) put(ColumnValue(model_, column, s));
  line_ += '\n';
  *out_ << line_;
}

}  // namespace tether
