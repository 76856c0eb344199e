#include "tether/dynamics/io/trajectory_csv.h"

#include <charconv>

#include "tether/dynamics/io/csv_line.h"
#include "tether/dynamics/model/errors.h"

namespace tether {

TrajectoryCsvWriter::TrajectoryCsvWriter(const Model<double>& model, std::ostream* out)
    : model_(model), columns_(TrajectoryColumns(model)), out_(out) {
  // names come from scene files and imported models, so may hold a comma or a quote: RFC 4180 quoting
  for (size_t i = 0; i < columns_.size(); ++i) *out_ << (i ? "," : "") << CsvCell(columns_[i].name);
  *out_ << '\n';
}

namespace {

// the shortest form of x that reads back as x, appended to *line after a comma unless it starts the line
void AppendNumber(double x, std::string* line) {
  char number[32];
  const std::to_chars_result end = std::to_chars(number, number + sizeof number, x);
  if (!line->empty()) *line += ',';
  line->append(number, end.ptr);
}

}  // namespace

void TrajectoryCsvWriter::Write(const Sample<double>& s) {
  line_.clear();
  for (const TrajectoryColumn& column : columns_) AppendNumber(ColumnValue(model_, column, s), &line_);
  line_ += '\n';
  *out_ << line_;
}

void WriteEventsCsv(const std::vector<RunEvent>& events, std::ostream* out) {
  *out << "t,kind,constraint,speed_before,speed_after\n";
  std::string line;
  for (const RunEvent& e : events) {
    line.clear();
    AppendNumber(e.t, &line);
    line += "," + e.kind + "," + CsvCell(e.constraint);
    AppendNumber(e.speed_before, &line);
    AppendNumber(e.speed_after, &line);
    *out << line << '\n';
  }
}

}  // namespace tether
