// tether._tether.Stepper: a run that Python takes step by step (docs/stepping.md), for controllers written in
// Python. It owns its copy of the scene's model, which its Stepper reads and SetControl writes; every step's sample
// is recorded as `simulate` records it, so that trajectory() is the run's Trajectory (bit for bit simulate's when
// no control is set). The GIL is released while it steps, and Ctrl-C stops it at its next step.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.h"
#include "tether/dynamics/integration/controls.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/io/request_limits.h"
#include "tether/dynamics/io/settings_overrides.h"
#include "tether/dynamics/io/trajectory_columns.h"

namespace tether::python {
namespace {

// What set_state puts back: the stepper's carry, the controls, and where the recording was (its branch and how
// many rows and events it held).
struct SavedState {
  const void* owner = nullptr;
  Stepper<double>::Carry carry;
  ControlSettings controls;
  int branch = 0;
  size_t rows = 0, events = 0;
};

class SteppedRun {
 public:
  // Its stepper emits every step's sample (so that a column's value now is always at hand); the recording keeps
  // every `every`-th step's, the first and the last, as simulate's does.
  SteppedRun(const Scene& scene, const SettingsOverrides& overrides, int every)
      : scene_{scene.path, {}, scene.model, {}}, every_(every) {
    CheckCount(every, 1, std::numeric_limits<int>::max(), "every");
    overrides.Apply(&scene_.model, "");
    columns_ = TrajectoryColumns(scene_.model);
    ExpectedRows(scene_.path, scene_.model, columns_.size(), every);
    now_.resize(columns_.size());
    OnScene(scene_, [&] {
      stepper_ =
          std::make_unique<Stepper<double>>(scene_.model, RunOptions{}, [this](const Sample<double>& s) { Record(s); });
      steps_ = stepper_->steps_left();
      stepper_->Start();
      return 0;
    });
  }

  double time() const { return Idle().time(); }
  double end() const { return scene_.model.simulation.duration; }

  void Step(int n) {
    CheckCount(n, 0, std::numeric_limits<int>::max(), "n");
    if (n > Idle().steps_left()) {
      throw InputError(scene_.path + ": " + std::to_string(n) + (n == 1 ? " step" : " steps") +
                       " would pass the run's end at t = " + Number(end()) + " s (" +
                       std::to_string(stepper_->steps_left()) + " are left): make the stepper with a longer duration");
    }
    Run([&] {
      for (int k = 0; k < n; ++k) stepper_->Step();
    });
  }

  // Steps until the time reaches t, to within a millionth of a step: onto the first grid time at or after t.
  void StepTo(double t) {
    if (!std::isfinite(t)) throw InputError(scene_.path + ": t = " + Number(t) + " is not a time");
    if (t > end() * (1.0 + 1e-12)) {
      throw InputError(scene_.path + ": t = " + Number(t) + " is past the run's end at t = " + Number(end()) +
                       " s: make the stepper with a longer duration");
    }
    const double slack = 1e-6 * scene_.model.simulation.step;
    Run([&] {
      while (stepper_->time() < t - slack && stepper_->Step()) {
      }
    });
  }

  // A trajectory column's value now.
  double Column(const std::string& name) const {
    Idle();
    for (size_t c = 0; c < columns_.size(); ++c) {
      if (columns_[c].name == name) return now_[c];
    }
    throw py::key_error("no column '" + name + "' (the columns are those of the scene's trajectory CSV)");
  }
  std::vector<std::string> Columns() const {
    std::vector<std::string> names;
    for (const TrajectoryColumn& column : columns_) names.push_back(column.name);
    return names;
  }

  py::array_t<double> q() const { return Copy(Idle().state().q); }
  py::array_t<double> v() const { return Copy(Idle().state().v); }

  void SetControl(const std::string& name, double value) {
    Idle();
    tether::SetControl(Find(name), value, &scene_.model);
  }
  double ControlNow(const std::string& name) const { return ControlValue(Find(name), scene_.model, time()); }

  SavedState Save() const { return {this, Idle().Save(), SaveControls(scene_.model), branch_, rows_, events_.size()}; }
  // The recording keeps the path to the state now: a state saved on it cuts the recording back to where it was
  // saved; one saved on a path since left (a rollout abandoned) starts the recording again at that state.
  void Restore(const SavedState& state) {
    if (state.owner != this) throw InputError(scene_.path + ": that state was saved by another stepper");
    Idle().Restore(state.carry);
    RestoreControls(state.controls, &scene_.model);
    failed_.clear();
    refresh_only_ = OnThePath(state.branch, state.rows);  // the state's row is in the recording already
    if (refresh_only_) {
      Truncate(state.rows, state.events);
      branches_.push_back({state.branch, state.rows});
    } else {
      Truncate(0, 0);
      branches_.push_back({-1, 0});
    }
    stepper_->Start();  // the columns' values now (and the first row of a recording started again)
    refresh_only_ = false;
    branch_ = static_cast<int>(branches_.size()) - 1;
  }

  Recorded Trajectory() const {
    Idle();
    Recorded out;
    for (const TrajectoryColumn& column : columns_) out.columns.push_back(column.name);
    out.table = TakeMatrix(std::vector<double>(table_), rows_, columns_.size());
    out.q = TakeMatrix(std::vector<double>(q_), rows_, q_size());
    out.v = TakeMatrix(std::vector<double>(v_), rows_, v_size());
    out.events = EventRows(events_);
    return out;
  }

 private:
  size_t q_size() const { return static_cast<size_t>(scene_.model.NumCoordinates()); }
  size_t v_size() const { return static_cast<size_t>(scene_.model.NumVelocities()); }

  static std::string Number(double x) {
    std::ostringstream out;
    out.precision(9);
    out << x;
    return out.str();
  }

  static py::array_t<double> Copy(const VecX<double>& x) {
    py::array_t<double> out(x.size());
    std::copy(x.data(), x.data() + x.size(), out.mutable_data());
    return out;
  }

  // Whether rows [0, rows) of branch b are rows of the path to the state now: b is the current branch or one it
  // forked from, at or after `rows`.
  bool OnThePath(int b, size_t rows) const {
    size_t limit = rows_;
    for (int c = branch_; c >= 0; limit = branches_[c].fork_rows, c = branches_[c].parent) {
      if (c == b) return rows <= limit;
    }
    return false;
  }

  tether::Control Find(const std::string& name) const {
    try {
      return FindControl(scene_.model, name);
    } catch (const InputError& e) {
      throw InputError(scene_.path + ": " + e.what());
    }
  }

  void Record(const Sample<double>& s) {
    for (size_t c = 0; c < columns_.size(); ++c) now_[c] = ColumnValue(scene_.model, columns_[c], s);
    const std::int64_t left = stepper_->steps_left(), step = steps_ - left;
    if (refresh_only_ || !(rows_ == 0 || step % every_ == 0 || left == 0)) return;
    table_.insert(table_.end(), now_.begin(), now_.end());
    q_.insert(q_.end(), s.q.data(), s.q.data() + s.q.size());
    v_.insert(v_.end(), s.v.data(), s.v.data() + s.v.size());
    ++rows_;
  }

  // Steps with the GIL released; the events the steps reported join the recording. After a failure the run
  // cannot go on (its state is where the failure left it) until a saved state is put back.
  template <typename Work>
  void Run(Work work) {
    Idle();
    if (!failed_.empty()) {
      throw InputError(scene_.path + ": the run stopped (" + failed_ + "); set_state() a saved state to go on");
    }
    struct Stepping {  // set while the lock is released, so that another thread's calls are refused
      bool& flag;
      explicit Stepping(bool& f) : flag(f) { flag = true; }
      ~Stepping() { flag = false; }
    } stepping(stepping_);
    try {
      OnScene(scene_, [&] {
        work();
        return 0;
      });
    } catch (const SimulationDiverged& e) {
      failed_ = e.what();
      TakeEvents();
      throw;
    }
    TakeEvents();
  }

  // The stepper, when no other thread is stepping it (its calls hold the interpreter's lock; stepping releases it).
  Stepper<double>& Idle() const {
    if (stepping_) throw InputError(scene_.path + ": the stepper is stepping in another thread");
    return *stepper_;
  }

  void TakeEvents() {
    const std::vector<RunEvent>& all = stepper_->report().events;
    for (; seen_events_ < all.size(); ++seen_events_) events_.push_back(all[seen_events_]);
  }

  void Truncate(size_t rows, size_t events) {
    rows_ = std::min(rows, rows_);
    table_.resize(rows_ * columns_.size());
    q_.resize(rows_ * q_size());
    v_.resize(rows_ * v_size());
    events_.resize(std::min(events, events_.size()));
    seen_events_ = stepper_->report().events.size();
  }

  Scene scene_;  // its model is the one the stepper reads and the controls write
  int every_;
  std::int64_t steps_ = 0;  // of the whole run
  std::vector<TrajectoryColumn> columns_;
  std::vector<double> now_;    // the columns' values now
  bool refresh_only_ = false;  // while set, a sample updates now_ and records no row
  std::unique_ptr<Stepper<double>> stepper_;
  std::vector<double> table_, q_, v_;
  size_t rows_ = 0;
  std::vector<RunEvent> events_;
  size_t seen_events_ = 0;
  std::string failed_;
  bool stepping_ = false;
  struct Branch {
    int parent;        // the branch it forked from, -1 for a recording started afresh
    size_t fork_rows;  // the parent's rows it kept
  };
  std::vector<Branch> branches_ = {{-1, 0}};
  int branch_ = 0;
};

}  // namespace

void BindStepper(py::module_& m) {
  py::class_<SavedState>(m, "SavedState");
  py::class_<SteppedRun>(m, "Stepper")
      .def(py::init<const Scene&, const SettingsOverrides&, int>())
      .def_property_readonly("t", &SteppedRun::time)
      .def_property_readonly("end", &SteppedRun::end)
      .def_property_readonly("q", &SteppedRun::q)
      .def_property_readonly("v", &SteppedRun::v)
      .def("column", &SteppedRun::Column)
      .def("columns", &SteppedRun::Columns)
      .def("step", &SteppedRun::Step)
      .def("step_to", &SteppedRun::StepTo)
      .def("set_control", &SteppedRun::SetControl)
      .def("control", &SteppedRun::ControlNow)
      .def("state", &SteppedRun::Save)
      .def("set_state", &SteppedRun::Restore)
      .def("trajectory", &SteppedRun::Trajectory);
}

}  // namespace tether::python
