#include "tether/autodiff/observations.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>

#include "tether/dynamics/io/csv_line.h"
#include "tether/dynamics/io/input_file.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// The cells of one line (csv_line.h: quoted names keep their commas), without a Windows line end; fail(message)
// when a quote is not closed.
template <typename Fail>
std::vector<std::string> SplitCells(const std::string& line, Fail fail) {
  const bool crlf = !line.empty() && line.back() == '\r';
  std::optional<std::vector<std::string>> cells = SplitCsvLine(crlf ? line.substr(0, line.size() - 1) : line);
  if (!cells) fail("a quoted cell is not closed, or text follows its closing quote");
  return *cells;
}

std::string Trim(std::string s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  const size_t end = s.find_last_not_of(" \t\r");
  return begin == std::string::npos ? "" : s.substr(begin, end - begin + 1);
}

// Column name -> where its value lives, for every trajectory column of the model that can be observed, named as
// a trajectory CSV writes it (csv_line.h: a line break in a name, which URDF and MJCF names may hold, is a space).
std::map<std::string, TrajectoryColumn> KnownColumns(const Model<double>& model) {
  std::map<std::string, TrajectoryColumn> known;
  for (const TrajectoryColumn& column : TrajectoryColumns(model)) {
    if (column.kind == TrajectoryColumn::Kind::kTime || column.kind == TrajectoryColumn::Kind::kConstraintError) continue;
    std::string written = column.name;
    std::replace_if(
        written.begin(), written.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    known[written] = column;
  }
  return known;
}

// The observed columns a header names (obs->columns) and the position of its `t` (-1 if none); a whole
// trajectory's `constraint_error` is left out (-2). fail(message) for a bad header.
template <typename Fail>
std::vector<int> ReadHeader(const std::vector<std::string>& names, const Model<double>& model, bool trajectory,
                            Observations* obs, int* time_column, Fail fail) {
  const std::map<std::string, TrajectoryColumn> known = KnownColumns(model);
  *time_column = -1;
  std::vector<int> column_of_cell(names.size(), -1);  // data column of each cell, -1 for t
  for (size_t c = 0; c < names.size(); ++c) {
    const std::string name = Trim(names[c]);
    if (name == "t") {
      if (*time_column >= 0) fail("the column 't' appears twice");
      *time_column = static_cast<int>(c);
      continue;
    }
    if (name == "constraint_error" && trajectory) {
      column_of_cell[c] = -2;
      continue;
    }
    if (name == "constraint_error") fail("'constraint_error' is a diagnostic and cannot be observed");
    const auto it = known.find(name);
    if (it == known.end()) {
      fail("unknown column '" + name + "' (expected t and trajectory columns such as " +
           TrajectoryColumns(model)[1].name + ")");
    }
    for (const TrajectoryColumn& seen : obs->columns) {
      if (seen.name == name) fail("the column '" + name + "' appears twice");
    }
    column_of_cell[c] = static_cast<int>(obs->columns.size());
    obs->columns.push_back(it->second);
  }
  if (*time_column < 0) fail("no 't' column");
  if (obs->columns.empty()) fail("no observed column besides 't'");
  return column_of_cell;
}

// Adds a row of numbers (NaN: missing) at its place `line`; fail(message) for a missing or out-of-range time.
template <typename Fail>
void AddRow(const std::vector<double>& cells, const std::vector<int>& column_of_cell, int time_column, int line,
            const Model<double>& model, Observations* obs, Fail fail) {
  const double t = cells[time_column];
  if (std::isnan(t)) fail("the time 't' is missing");
  const double duration = model.simulation.duration;
  if (!(t >= 0.0 && t <= duration * (1 + 1e-12))) {
    std::ostringstream message;
    message.precision(17);
    message << "t = " << t << " lies outside the simulated interval [0, " << duration << "]";
    fail(message.str());
  }
  std::vector<double> row(obs->columns.size(), NAN);
  for (size_t c = 0; c < cells.size(); ++c) {
    if (column_of_cell[c] >= 0) row[column_of_cell[c]] = cells[c];
  }
  obs->times.push_back(t);
  obs->values.push_back(row);
  obs->lines.push_back(line);
}

// Rows in time order, one row per time; `unit` ("line", "row") names a row's place in messages.
Observations Sorted(const Observations& obs, const std::string& unit) {
  std::vector<size_t> order(obs.times.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&obs](size_t a, size_t b) { return obs.times[a] < obs.times[b]; });
  Observations sorted = obs;
  for (size_t k = 0; k < order.size(); ++k) {
    sorted.times[k] = obs.times[order[k]];
    sorted.values[k] = obs.values[order[k]];
    sorted.lines[k] = obs.lines[order[k]];
    if (k > 0 && sorted.times[k] == sorted.times[k - 1]) {
      throw InputError(obs.path + ": " + unit + " " + std::to_string(sorted.lines[k]) + ": repeats the time of " +
                       unit + " " + std::to_string(sorted.lines[k - 1]));
    }
  }
  return sorted;
}

// The rows read, refused when there is nothing to fit (no row, or no value besides the times: every residual would
// be empty and any parameters would "fit"), in time order. `what` names the source, `unit` a row's place.
Observations Finished(const Observations& obs, const std::string& what, const std::string& unit) {
  if (obs.times.empty()) throw InputError(obs.path + ": " + what + " has no rows");
  if (obs.CellCount() == 0) {
    throw InputError(obs.path + ": " + what + " has no observed value: every cell besides 't' is empty");
  }
  return Sorted(obs, unit);
}

}  // namespace

int Observations::CellCount() const {
  int count = 0;
  for (const auto& row : values) {
    for (double v : row) count += std::isnan(v) ? 0 : 1;
  }
  return count;
}

bool ObservesEnergy(const Observations& observations) {
  return std::any_of(observations.columns.begin(), observations.columns.end(),
                     [](const TrajectoryColumn& c) { return c.kind == TrajectoryColumn::Kind::kEnergy; });
}

namespace {

Observations Read(const std::string& path, const Model<double>& model, bool trajectory) {
  CheckInputFile(path, "data file", kMaxDataBytes);
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the data file");
  int line = 1;
  auto fail = [&path, &line](const std::string& message) {
    throw InputError(path + ": line " + std::to_string(line) + ": " + message);
  };
  Observations obs;
  obs.path = path;
  std::string text;
  if (!std::getline(in, text)) throw InputError(path + ": the data file is empty (it needs a header row)");
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark is not part of a name
  const std::vector<std::string> header = SplitCells(text, fail);
  int time_column = -1;
  const std::vector<int> column_of_cell = ReadHeader(header, model, trajectory, &obs, &time_column, fail);
  for (line = 2; std::getline(in, text); ++line) {
    if (Trim(text).empty()) continue;
    const std::vector<std::string> cells = SplitCells(text, fail);
    if (cells.size() != header.size()) {
      fail("expected " + std::to_string(header.size()) + " cells, got " + std::to_string(cells.size()));
    }
    std::vector<double> numbers(cells.size(), NAN);
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string cell = Trim(cells[c]);
      if (cell.empty()) continue;
      char* end = nullptr;
      numbers[c] = std::strtod(cell.c_str(), &end);
      if (end != cell.c_str() + cell.size() || !std::isfinite(numbers[c])) {
        fail("column '" + Trim(header[c]) + "': '" + cell + "' is not a finite number");
      }
    }
    AddRow(numbers, column_of_cell, time_column, line, model, &obs, fail);
  }
  return Finished(obs, "the data file", "line");
}

}  // namespace

Observations ReadObservations(const std::string& path, const Model<double>& model) { return Read(path, model, false); }

Observations ReadTrajectory(const std::string& path, const Model<double>& model) { return Read(path, model, true); }

Observations MakeObservations(const std::string& source, const std::vector<std::string>& names,
                              const std::vector<std::vector<double>>& rows, const Model<double>& model) {
  Observations obs;
  obs.path = source;
  int row = 0;
  auto fail = [&source, &row](const std::string& message) {
    throw InputError(source + (row > 0 ? ": row " + std::to_string(row) : std::string()) + ": " + message);
  };
  int time_column = -1;
  const std::vector<int> column_of_cell = ReadHeader(names, model, false, &obs, &time_column, fail);
  for (row = 1; row <= static_cast<int>(rows.size()); ++row) {
    const std::vector<double>& cells = rows[row - 1];
    if (cells.size() != names.size()) {
      fail("expected " + std::to_string(names.size()) + " values, got " + std::to_string(cells.size()));
    }
    for (size_t c = 0; c < cells.size(); ++c) {
      if (std::isinf(cells[c])) fail("column '" + names[c] + "': the value is infinite");
    }
    AddRow(cells, column_of_cell, time_column, row, model, &obs, fail);
  }
  return Finished(obs, "the data", "row");
}

}  // namespace tether
