// tether._tether: the C++ side of the Python module (python/tether/__init__.py is the API users see). It is a thin
// shell over the libraries: results cross as the JSON text the command line prints (tether.gradient, tune,
// identify, fit, check return what `tether gradient` ... print), trajectories as NumPy arrays that own the memory
// the run filled (no copy), data as the names and rows of a table.
//
// During every run the GIL is released, and a CancelRuns (interrupts.h) is held: Ctrl-C stops the run at its next
// step and raises KeyboardInterrupt here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bindings.h"
#include "tether/autodiff/gradient_method.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/request_limits.h"
#include "tether/dynamics/io/scene_check.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/settings_overrides.h"
#include "tether/dynamics/io/trajectory_columns.h"
#include "tether/dynamics/model/errors.h"
#include "tether/studies/study.h"
#include "tether/tuning/identify.h"
#include "tether/tuning/optimizer.h"
#include "tether/tuning/reports.h"
#ifdef TETHER_HAVE_VIEWER
#include "tether/viewer/view.h"
#endif

namespace tether::python {
namespace {

// A run of the scene with `overrides` in place of its settings, every `every`-th step recorded.
Recorded SimulateScene(const Scene& scene, const SettingsOverrides& overrides, int every) {
  CheckCount(every, 1, std::numeric_limits<int>::max(), "every");
  Model<double> model = scene.model;
  overrides.Apply(&model, "");
  const std::vector<TrajectoryColumn> columns = TrajectoryColumns(model);
  const size_t nq = model.NumCoordinates(), nv = model.NumVelocities();
  const size_t expected_rows = ExpectedRows(scene.path, model, columns.size(), every);
  std::vector<double> table, q, v;
  table.reserve(expected_rows * columns.size());
  q.reserve(expected_rows * nq);
  v.reserve(expected_rows * nv);
  size_t rows = 0;
  RunReport report;
  OnScene(scene, [&] {
    RunOptions options;
    options.every = every;
    report = Simulate<double>(model, options, [&](const Sample<double>& s) {
      for (const TrajectoryColumn& column : columns) table.push_back(ColumnValue(model, column, s));
      q.insert(q.end(), s.q.data(), s.q.data() + nq);
      v.insert(v.end(), s.v.data(), s.v.data() + nv);
      ++rows;
    });
    return 0;
  });
  Recorded out;
  for (const TrajectoryColumn& column : columns) out.columns.push_back(column.name);
  out.table = TakeMatrix(std::move(table), rows, columns.size());
  out.q = TakeMatrix(std::move(q), rows, nq);
  out.v = TakeMatrix(std::move(v), rows, nv);
  out.events = EventRows(report.events);
  return out;
}

// The page of tether view for a recorded run of the scene (Trajectory.view(), docs/view.md): its table (the
// trajectory's columns), configurations and events.
std::string ViewOf(const Scene& scene, const py::array_t<double, py::array::c_style | py::array::forcecast>& table,
                   const py::array_t<double, py::array::c_style | py::array::forcecast>& q,
                   const std::vector<EventRow>& events) {
#ifndef TETHER_HAVE_VIEWER
  throw InputError(
      "this tether was built without the viewer (-DTETHER_VIEWER=OFF): install libjs-three and "
      "configure with -DTETHER_VIEWER=ON");
#else
  const Model<double>& model = scene.model;
  const std::vector<TrajectoryColumn> columns = TrajectoryColumns(model);
  const py::ssize_t nq = model.NumCoordinates();
  if (table.ndim() != 2 || table.shape(1) != static_cast<py::ssize_t>(columns.size()) || q.ndim() != 2 ||
      q.shape(1) != nq || q.shape(0) != table.shape(0) || table.shape(0) == 0) {
    throw InputError(scene.path + ": the trajectory is not a run of this scene (its columns or its rows differ)");
  }
  const auto rows = table.unchecked<2>();
  const auto configurations = q.unchecked<2>();
  std::vector<double> times(table.shape(0));
  for (py::ssize_t r = 0; r < table.shape(0); ++r) times[r] = rows(r, 0);
  std::vector<int> plotted;
  std::vector<std::string> names;
  for (size_t c = 0; c < columns.size(); ++c) {
    if (!PlottedColumn(columns[c])) continue;
    plotted.push_back(static_cast<int>(c));
    names.push_back(columns[c].name);
  }
  ViewFrames frames = SampledFrames(
      scene.path, model, times,
      [&](size_t r) {
        VecX<double> x(nq);
        for (py::ssize_t k = 0; k < nq; ++k) x[k] = configurations(r, k);
        return x;
      },
      names,
      [&](size_t r) {
        std::vector<double> values;
        for (int c : plotted) values.push_back(rows(r, c));
        return values;
      });
  for (const auto& [t, kind, constraint, before, after, point, normal, impulse] : events) {
    frames.events.push_back({t, kind, constraint, Vec3<double>(point.data()), Vec3<double>(normal.data()), impulse});
  }
  return ViewHtml(model, std::filesystem::path(scene.path).filename().string(), frames);
#endif
}

// A table of observations: column names and a rows x columns array (NaN: missing).
Observations Data(const std::string& source, const std::vector<std::string>& names,
                  const py::array_t<double, py::array::c_style | py::array::forcecast>& values,
                  const Model<double>& model) {
  if (values.ndim() != 2 || static_cast<size_t>(values.shape(1)) != names.size()) {
    throw InputError(source + ": expected a table of " + std::to_string(names.size()) + " columns");
  }
  std::vector<std::vector<double>> rows(values.shape(0));
  const auto view = values.unchecked<2>();
  for (py::ssize_t r = 0; r < values.shape(0); ++r) {
    rows[r].resize(names.size());
    for (size_t c = 0; c < names.size(); ++c) rows[r][c] = view(r, c);
  }
  return MakeObservations(source, names, rows, model);
}

std::string GradientOf(const Scene& scene, const std::vector<std::string>& names,
                       const py::array_t<double, py::array::c_style | py::array::forcecast>& values,
                       const std::vector<std::string>& pointers, const std::string& method,
                       const std::vector<std::string>& ties) {
  const GradientMethod requested = ParseGradientMethod(method, "method");
  ParameterSet parameters(scene, pointers);
  parameters.Tie(scene, ties, "ties");
  const Observations observations = Data("data", names, values, scene.model);
  return OnScene(scene, [&] {
    const auto start = std::chrono::steady_clock::now();
    const GradientMethod used = ResolveGradientMethod(requested, parameters.size());
    AdjointReport adjoint;
    const LossGradient result = LossGradientBy(used, scene.model, parameters, observations, &adjoint);
    bool finite = std::isfinite(result.loss);
    for (double g : result.gradient) finite = finite && std::isfinite(g);
    if (!finite) {  // a failure, never a result (the command line exits 1)
      throw SimulationDiverged(
          "the loss or its gradient is not finite (an overflow in the simulation or its derivatives)", 0.0, -1);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return GradientJson(parameters, scene.model, result, used, seconds, adjoint).dump();
  });
}

// Tunes the gains of the scene with `overrides` (duration, step, integrator, solver: the gains and the
// stabilization are what it chooses, so Python never sets them here) in place of its settings.
std::string TuneScene(const Scene& scene, const SettingsOverrides& overrides, const std::string& objective,
                      const std::string& optimizer, int samples, int max_evaluations) {
  Model<double> model = scene.model;
  overrides.Apply(&model, "");
  TuneSettings settings;
  if (objective == "reference") {
    settings.objective.kind = GainObjectiveKind::kReference;
  } else if (objective == "drift") {
    settings.objective.kind = GainObjectiveKind::kDrift;
  } else {
    throw InputError("objective: unknown objective '" + objective + "' (expected reference or drift)");
  }
  CheckCount(samples, 1, kMaxSamples, "samples");
  CheckCount(max_evaluations, 2, kMaxEvaluations, "max_evaluations");
  CheckOptimizerName(optimizer, "optimizer");
  settings.objective.samples = samples;
  settings.optimizer.name = optimizer;
  settings.optimizer.max_evaluations = max_evaluations;
  return OnScene(scene, [&] {
    try {
      return TuneJson(TuneGains(model, settings), objective, optimizer, model.simulation.step).dump();
    } catch (const SimulationDiverged& e) {
      throw SimulationDiverged(std::string("the reference motion diverged: ") + e.what(), e.time(), e.constraint());
    }
  });
}

// The segments argument the Python fit passes for segments=None: fit chooses, as the command line does.
constexpr int kAutomaticSegments = -1;

struct Dataset {
  std::string source;
  std::vector<std::string> names;
  py::array_t<double, py::array::c_style | py::array::forcecast> values;
};

std::string IdentifyParameters(const Scene& scene, const std::vector<Dataset>& datasets,
                               const std::vector<std::string>& pointers,
                               const std::vector<std::tuple<std::string, double, double>>& bounds, int segments,
                               const std::string& loss, const std::string& optimizer, int max_evaluations,
                               double smooth, const std::string& method, const std::vector<std::string>& ties,
                               double effort, const std::vector<std::string>& at_least,
                               const std::vector<std::string>& at_most, int starts, unsigned seed) {
  IdentifySettings settings;
  for (const std::string& text : at_least) settings.inequalities.push_back(ParseInequality(text, true, "at_least"));
  for (const std::string& text : at_most) settings.inequalities.push_back(ParseInequality(text, false, "at_most"));
  if (!(effort >= 0) || !std::isfinite(effort)) throw InputError("effort: must be >= 0");
  CheckCount(starts, 1, kMaxStarts, "starts");
  settings.effort = effort;
  settings.starts = starts;
  settings.seed = seed;
  CheckOptimizerName(optimizer, "optimizer");
  settings.optimizer.name = optimizer;
  settings.method = ParseGradientMethod(method, "method");
  if (!loss.empty()) settings.optimizer.loss = ParseRobustLoss(loss, "loss");
  if (segments != kAutomaticSegments) CheckCount(segments, 1, kMaxSegments, "segments");
  CheckCount(max_evaluations, 2, kMaxEvaluations, "max_evaluations");
  if (!(smooth >= 0) || !std::isfinite(smooth)) throw InputError("smooth: must be >= 0");
  settings.segments = segments == kAutomaticSegments ? 0 : segments;  // fit's choice (trajectory_fit.h)
  settings.smooth = smooth;
  settings.optimizer.max_evaluations = max_evaluations;
  ParameterSet parameters(scene, pointers);
  parameters.Tie(scene, ties, "ties");
  std::vector<ParameterBound> checked;
  for (const auto& [pointer, lo, hi] : bounds) {
    if (!(lo < hi)) throw InputError("bounds: '" + pointer + "': the lower bound must be below the upper");
    checked.push_back({pointer, lo, hi});
  }
  settings.bounds = BoundsFor(parameters, checked, "bounds");
  std::vector<Observations> recordings;
  for (const Dataset& d : datasets) recordings.push_back(Data(d.source, d.names, d.values, scene.model));
  return OnScene(scene, [&] {
    return IdentifyJson(parameters, Identify(scene.model, parameters, recordings, settings), optimizer).dump();
  });
}

// Runs (or resumes) a study into `folder`; its results are folder/results.csv, as `tether study` writes them.
void RunStudyFile(const std::string& path, const std::string& folder, int threads, bool restart) {
  const StudySpec spec = ReadStudySpec(path);
  CheckCount(threads, 1, kMaxThreads, "threads");
  Interruptible([&] { return RunStudy(spec, folder, threads, restart, [](int, int, double) {}); });
}

}  // namespace
}  // namespace tether::python

PYBIND11_MODULE(_tether, m) {
  using namespace tether;
  using namespace tether::python;
  m.doc() = "tether's C++ core; use the tether package (python/tether/__init__.py)";
  m.attr("__version__") = TETHER_VERSION;
  m.attr("TRAJECTORY_OPTIMIZER") = kTrajectoryOptimizer;  // fit's defaults with constraints or starts
  m.attr("TRAJECTORY_MAX_EVALUATIONS") = kTrajectoryMaxEvaluations;
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<SimulationDiverged>(m, "SimulationDiverged", PyExc_RuntimeError);
  py::register_exception<OutputError>(m, "OutputError", PyExc_OSError);

  py::class_<Scene>(m, "Scene")
      .def_static("load", &ReadSceneFile, py::arg("path"))
      .def_static("parse", [](const std::string& text,
                              const std::string& name) { return ParseScene(ParseJsonText(text, name), name); })
      .def_readonly("path", &Scene::path)
      .def("text", [](const Scene& s) { return s.document.dump(); });

  py::class_<Recorded>(m, "Recorded")
      .def_readonly("columns", &Recorded::columns)
      .def_readonly("table", &Recorded::table)
      .def_readonly("q", &Recorded::q)
      .def_readonly("v", &Recorded::v)
      .def_readonly("events", &Recorded::events);
  py::class_<SettingsOverrides>(m, "SettingsOverrides")
      .def(py::init<>())
      .def_readwrite("duration", &SettingsOverrides::duration)
      .def_readwrite("step", &SettingsOverrides::step)
      .def_readwrite("integrator", &SettingsOverrides::integrator)
      .def_readwrite("alpha", &SettingsOverrides::alpha)
      .def_readwrite("beta", &SettingsOverrides::beta)
      .def_readwrite("solver", &SettingsOverrides::solver)
      .def_readwrite("stabilization", &SettingsOverrides::stabilization);
  m.def("simulate", &SimulateScene);
  m.def("gradient", &GradientOf);
  m.def("tune", &TuneScene);
  py::class_<Dataset>(m, "Dataset")
      .def(py::init<std::string, std::vector<std::string>,
                    py::array_t<double, py::array::c_style | py::array::forcecast>>());
  m.def("identify", &IdentifyParameters);
  m.def("check", [](const Scene& scene) { return SceneCheckJson(CheckScene(scene.model)).dump(); });
  m.def("study", &RunStudyFile);
  m.def("view_html", &ViewOf);
  BindStepper(m);
}
