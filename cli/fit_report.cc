#include "fit_report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "fit_plot.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/trajectory_columns.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/reports.h"
#include "tether/viewer/pages.h"
#include "tether/viewer/view.h"

namespace tether::cli {
namespace {

// A line of the page holds at most this many points (more are thinned evenly: every k-th, and the last).
constexpr size_t kMostPlottedPoints = 4000;

size_t Stride(size_t count) { return std::max<size_t>(1, (count + kMostPlottedPoints - 1) / kMostPlottedPoints); }

std::vector<double> Thinned(const std::vector<double>& values, size_t stride) {
  std::vector<double> kept;
  for (size_t k = 0; k < values.size(); k += stride) kept.push_back(values[k]);
  if (!values.empty() && (values.size() - 1) % stride != 0) kept.push_back(values.back());
  return kept;
}

// The residuals' statistics and histogram (fit_report.h).
nlohmann::json ResidualStatisticsJson(const std::vector<double>& r) {
  const double n = static_cast<double>(r.size());
  double bias = 0.0, squares = 0.0, largest = 0.0;
  for (const double x : r) {
    bias += x / n;
    squares += x * x / n;
    largest = std::max(largest, std::abs(x));
  }
  const double sigma = std::sqrt(squares);
  double lagged = 0.0, spread = 0.0;
  for (size_t i = 0; i < r.size(); ++i) {
    spread += (r[i] - bias) * (r[i] - bias);
    if (i + 1 < r.size()) lagged += (r[i] - bias) * (r[i + 1] - bias);
  }
  const double lag_one = spread > 0.0 ? lagged / spread : NAN;
  const double low = std::min(-4.0 * sigma, *std::min_element(r.begin(), r.end()));
  const double high = std::max(4.0 * sigma, *std::max_element(r.begin(), r.end()));
  const int bins = std::max(1, static_cast<int>(std::min(2.0 * std::sqrt(n), 60.0)));
  std::vector<int> counts(bins, 0);
  const double width = high > low ? (high - low) / bins : 1.0;
  for (const double x : r) ++counts[std::clamp(static_cast<int>((x - low) / width), 0, bins - 1)];
  return {{"count", r.size()},
          {"bias", bias},
          {"rms", sigma},
          {"sigma", sigma},
          {"lag_one", std::isfinite(lag_one) ? nlohmann::json(lag_one) : nlohmann::json()},
          {"largest", largest},
          {"low", low},
          {"high", high},
          {"counts", counts}};
}

const TrajectoryColumn& ColumnNamed(const std::vector<TrajectoryColumn>& columns, const std::string& name) {
  for (const TrajectoryColumn& column : columns) {
    if (column.name == name) return column;
  }
  throw InputError("no column " + name);  // the fit checked its columns
}

// The fit's own RMS of a recording's column (IdentifyResult::residuals), NaN where it has none.
double FitRms(const IdentifyResult& result, const std::string& file, const std::string& column) {
  for (const ResidualStatistics& s : result.residuals) {
    if (s.file == file && s.column == column) return s.rms;
  }
  return NAN;
}

}  // namespace

std::string FitReportHtml(const FitReportInput& in) {
  const Model<double>& model = *in.fitted;
  const std::vector<Observations>& recordings = *in.recordings;
  const std::vector<TrajectoryColumn> all = TrajectoryColumns(model);
  // the columns drawn: every recorded one, then the constrained ones the recordings leave out
  std::vector<TrajectoryColumn> drawn;
  const auto draw = [&](const std::string& name) {
    if (std::none_of(drawn.begin(), drawn.end(), [&](const TrajectoryColumn& c) { return c.name == name; })) {
      drawn.push_back(ColumnNamed(all, name));
    }
  };
  for (const Observations& recording : recordings) {
    for (const TrajectoryColumn& column : recording.columns) draw(column.name);
  }
  for (const InequalityTarget& target : *in.constraints) draw(target.column);

  // one run of the estimate: every drawn column on a grid of at most kMostPlottedPoints steps, and at the data's
  // times (stops; those at the start are the first sample's)
  const double start = 0.0;
  std::vector<double> stops;
  for (const Observations& recording : recordings) {
    for (const double t : recording.times) {
      if (t > start) stops.push_back(t);
    }
  }
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
  RunOptions options;
  options.stops = stops;
  options.every = static_cast<int>(Stride(static_cast<size_t>(model.simulation.duration / model.simulation.step)));
  std::vector<double> grid_times;
  std::vector<std::vector<double>> grid(drawn.size());
  std::map<double, std::vector<double>> at_time;  // data time -> the drawn columns' values
  std::string diverged;
  try {
    bool first = true;
    Simulate<double>(model, options, [&](const Sample<double>& s) {
      std::vector<double> values;
      for (const TrajectoryColumn& column : drawn) values.push_back(ColumnValue(model, column, s));
      if (first) at_time[start] = values;
      first = false;
      if (s.stop >= 0) at_time[stops[s.stop]] = values;
      if (!s.output) return;
      grid_times.push_back(s.t);
      for (size_t c = 0; c < drawn.size(); ++c) grid[c].push_back(values[c]);
    });
  } catch (const SimulationDiverged& e) {  // drawn as far as it went, and said
    diverged = e.what();
  }
  nlohmann::json simulated = {{"t", grid_times}, {"columns", nlohmann::json::object()}};
  for (size_t c = 0; c < drawn.size(); ++c) simulated["columns"][drawn[c].name] = NumbersOrNull(grid[c]);

  nlohmann::json columns = nlohmann::json::array();
  for (const Observations& recording : recordings) {
    for (size_t c = 0; c < recording.columns.size(); ++c) {
      const std::string& name = recording.columns[c].name;
      const size_t index =
          std::find_if(drawn.begin(), drawn.end(), [&](const TrajectoryColumn& d) { return d.name == name; }) -
          drawn.begin();
      std::vector<double> times, observed, residuals;
      for (size_t row = 0; row < recording.times.size(); ++row) {
        const double value = recording.values[row][c];
        if (std::isnan(value)) continue;
        const auto run = at_time.find(recording.times[row] > start ? recording.times[row] : start);
        times.push_back(recording.times[row]);
        observed.push_back(value);
        residuals.push_back(run == at_time.end() ? NAN : run->second[index] - value);
      }
      std::vector<double> finite;
      for (const double r : residuals) {
        if (std::isfinite(r)) finite.push_back(r);
      }
      const size_t stride = Stride(times.size());
      nlohmann::json entry = {{"file", recording.path},
                              {"column", name},
                              {"unit", ColumnUnit(name)},
                              {"stride", stride},
                              {"t", Thinned(times, stride)},
                              {"observed", NumbersOrNull(Thinned(observed, stride))},
                              {"residual", NumbersOrNull(Thinned(residuals, stride))},
                              {"fit_rms", NumbersOrNull({FitRms(*in.result, recording.path, name)})[0]}};
      entry["statistics"] = finite.empty() ? nlohmann::json() : ResidualStatisticsJson(finite);
      columns.push_back(entry);
    }
  }

  nlohmann::json report = IdentifyJson(*in.parameters, *in.result, in.optimizer);
  report["command"] = in.fit ? "fit" : "identify";
  report["scene"] = in.scene_path;
  report["pointers"] = in.parameters->pointers();  // in the command's order (the objects above sort them)
  report["data"] = nlohmann::json::array();
  for (const Observations& recording : recordings) report["data"].push_back(recording.path);
  report["columns"] = columns;
  report["constrained"] = nlohmann::json::array();
  for (const InequalityTarget& target : *in.constraints) {
    report["constrained"].push_back({{"column", target.column},
                                     {"unit", ColumnUnit(target.column)},
                                     {"from", target.from},
                                     {"t", target.time},
                                     {"value", target.value},
                                     {"at_least", target.at_least}});
  }
  report["simulated"] = simulated;
  report["schedules"] = nlohmann::json::array();
  for (const ScheduledEffect& effect : ScheduledEffects(model)) {
    report["schedules"].push_back({{"label", effect.label}, {"t", effect.times}, {"values", effect.values}});
  }
  report["run_diverged"] = diverged;

  ViewFrames frames;
  try {
    frames = SimulatedFrames(model);
  } catch (const SimulationDiverged&) {  // said above; the page plays no motion
  }
  report["run_warnings"] = frames.warnings;
  ViewFrames recorded;
  const bool beside = !recordings.empty() && !frames.times.empty();
  if (beside) recorded = ObservedFrames(model, recordings.front(), false);
  const std::string title = std::filesystem::path(in.scene_path).filename().string();
  const std::string view = frames.times.empty() ? "" : ViewHtml(model, title, frames, beside ? &recorded : nullptr);
  return ReportHtml("tether " + std::string(in.fit ? "fit" : "identify") + ": " + title, report, view);
}

}  // namespace tether::cli
