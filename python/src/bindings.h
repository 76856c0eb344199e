// What the C++ side of the Python module shares between its files (module.cc, stepping.cc): arrays handed over
// without a copy, runs with the GIL released and Ctrl-C stopping them, errors naming the scene, and a recorded
// run as tether.Trajectory takes it.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"

namespace tether::python {

namespace py = pybind11;

// A NumPy array of `rows` x `columns` that takes over `values` (row-major) without copying them.
inline py::array_t<double> TakeMatrix(std::vector<double>&& values, size_t rows, size_t columns) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>({rows, columns}, {columns * sizeof(double), sizeof(double)}, owned->data(),
                             free_when_done);
}

// Runs `work` with the GIL released and Ctrl-C stopping it; a stop is KeyboardInterrupt.
template <typename Work>
auto Interruptible(Work work) {
  try {
    const CancelRuns cancel;
    const py::gil_scoped_release release;
    return work();
  } catch (const RunInterrupted&) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
}

// Runs `work` on `scene` as Interruptible does; its InputError and SimulationDiverged name the scene's file (or
// the name given to from_dict) first, as the command line's messages do.
template <typename Work>
auto OnScene(const Scene& scene, Work work) {
  return Interruptible([&] {
    try {
      return work();
    } catch (const InputError& e) {
      throw InputError(scene.path + ": " + e.what());
    } catch (const SimulationDiverged& e) {
      throw SimulationDiverged(scene.path + ": " + e.what(), e.time(), e.constraint());
    }
  });
}

// An event as Python's tether.Event: t, kind, constraint, g'-, g'+, point, normal, impulse (RunEvent).
using EventRow =
    std::tuple<double, std::string, std::string, double, double, std::array<double, 3>, std::array<double, 3>, double>;

struct Recorded {
  std::vector<std::string> columns;
  py::array_t<double> table, q, v;
  std::vector<EventRow> events;
};

// The events of a run as Python's rows.
inline std::vector<EventRow> EventRows(const std::vector<RunEvent>& events) {
  const auto array = [](const Vec3<double>& x) { return std::array<double, 3>{x.x(), x.y(), x.z()}; };
  std::vector<EventRow> rows;
  for (const RunEvent& e : events) {
    rows.emplace_back(e.t, e.kind, e.constraint, e.speed_before, e.speed_after, array(e.point), array(e.normal),
                      e.impulse);
  }
  return rows;
}

// The rows a run of `model` recording every `every`-th step makes (t = 0 and the end included), refused up front
// (InputError) when they would hold more than 4 GiB rather than running out of memory at the end.
inline size_t ExpectedRows(const std::string& path, const Model<double>& model, size_t columns, int every) {
  constexpr double kMaxRecordingBytes = 4.0 * (1 << 30);
  const size_t numbers = columns + model.NumCoordinates() + model.NumVelocities();
  const size_t rows = static_cast<size_t>(StepCount(model.simulation) / every) + 2;
  if (8.0 * static_cast<double>(rows) * static_cast<double>(numbers) > kMaxRecordingBytes) {
    throw InputError(path + ": the run would record " + std::to_string(rows) + " rows of " + std::to_string(numbers) +
                     " numbers, more than the 4 GiB a recording may hold; record fewer rows (every) or simulate " +
                     "less (duration)");
  }
  return rows;
}

// Binds tether._tether.Stepper (stepping.cc).
void BindStepper(py::module_& m);

}  // namespace tether::python
