// Stepper<T>: a run (simulator.h) taken one step at a time. Simulate is
//   Stepper<T> stepper(model, options, observer);  stepper.Start();  while (stepper.Step()) {}
// and the discrete adjoint (autodiff/adjoint.h) saves the state between steps (checkpoints) and restores it to
// replay a step, recorded, in Rev arithmetic.
//
// The plan of a run: the grid t_k = start_time + k h (the last step shortened to land on the duration), each
// step split at a requested stop time that falls inside it. Step() takes one step of the plan (to the next grid
// time or to a stop), stabilizes, checks for divergence, and emits the samples due there. A scene with joint
// limits also splits a step at each event inside it (unilateral_events.h): the step is taken whole, and when a gap
// closed or an active limit's multiplier turned negative in it, the first such event is located by root finding
// on the step's size (Illinois' regula falsi on the event function, to kEventTimeTolerance of the step), the
// step is taken again up to the event, the event resolved, and the rest of the step taken the same way. In the
// time-stepping mode ("contact": "stepping") nothing is located: every step is taken whole and its end resolved by
// impulses (unilateral_stepping.cc).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "tether/dynamics/integration/integrators.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/unilateral_events.h"
#include "tether/dynamics/model/errors.h"

namespace tether {

// What a step depends on besides the model and the state: plain data, the same for every scalar (a Rev
// replay takes a double run's as it is): the position in the plan, what the integrator and the KKT solver carry
// (integrators.h, schur_solver.h), the joint angles' branches and the active joint limits.
struct StepperMemory {
  std::int64_t step = 0;  // grid steps taken
  double time = 0.0;
  size_t next_stop = 0;
  IntegratorMemory integrator;
  SolverMemory solver;
  std::vector<double> coordinate_branches;
  std::vector<char> active_sides;  // per side of a joint range or contact feature, with its friction
  std::vector<double> held_slips;  // and the sliding directions held (unilateral_events.h)
  std::vector<char> touching_sides;      // time stepping: the sides that overlapped at the step's end
  std::vector<double> contact_impulses;  // and their impulses there
  // bytes held besides the struct itself
  std::int64_t HeapBytes() const {
    return static_cast<std::int64_t>((coordinate_branches.size() + held_slips.size() + contact_impulses.size()) *
                                         sizeof(double) +
                                     active_sides.size() + touching_sides.size());
  }
};

template <typename T>
class Stepper {
 public:
  using Observer = std::function<void(const Sample<T>&)>;
  using Memory = StepperMemory;

  // Everything a step depends on besides the model: the state (q, v) and the memory.
  struct Carry {
    VecX<T> q, v;
    Memory memory;
  };

  // Validates the options, assembles the initial state onto the constraints (InputError when it cannot) and
  // builds the run's workspace. The model and the observer must outlive the stepper.
  Stepper(const Model<T>& model, const RunOptions& options, Observer observer);

  // Emits the samples at the start time.
  void Start();
  // Takes the next step of the plan and emits the samples due after it; false (and nothing done) once the run
  // has ended. Throws SimulationDiverged (and RunInterrupted when runs are cancelled, interrupts.h).
  bool Step();

  bool done() const { return step_ >= steps_; }
  double time() const { return time_; }                       // the time of the state now
  std::int64_t steps_left() const { return steps_ - step_; }  // of the plan (stops split one without counting)
  Carry Save() const;
  void Restore(const Carry& carry);
  // Save into an existing carry, reusing its storage.
  void SaveInto(Carry* carry) const;
  const RunReport& report() const { return report_; }
  const State<T>& state() const { return state_; }          // (q, v) now
  // the joint limits' sides and the contact features, and which are active
  const UnilateralEvents<T>& gaps() const { return gaps_; }
  const JointCoordinates<T>& coordinates() const { return ws_.coordinates; }  // their values now (`last`)
  // The KKT log of the steps to come (kkt_log.h), or nullptr: a double stepper keeps its solves in it, a Rev
  // stepper replaying the same step takes them back.
  void set_kkt_log(KktLog* log) { ws_.kkt_log = log; }

 private:
  void Emit(double t, bool output, int stop);
  void Advance(double t, double dt);
  void AdvanceSmooth(double t, double dt);
  bool CollectDue(double t);
  double FirstEvent(double t, double dt);
  double Locate(int side, double t, double dt);
  SimulationDiverged Diverged(double t, const std::string& what) const;
  void CheckViolation(double t, double largest) const;
  void WarnOfDrift(double t, double largest);
  bool Settle(double t, VecX<T>* q, VecX<T>* v);
  StepStatus RetakeSingularPass(double t, double dt);
  int StopAt(double t);

  const Model<T>& model_;
  RunOptions options_;
  Observer observer_;
  RunReport report_;
  State<T> state_;  // (q, v) now
  Workspace<T> ws_;
  TimeIntegrator<T> integrator_;
  double scale_, h_;
  std::int64_t steps_;
  std::int64_t step_ = 0;
  double time_ = 0.0;
  size_t next_stop_ = 0;
  VecX<T> coordinates_, rates_, q_projected_, v_projected_;
  VecX<T> q_values_, v_values_;  // the state's values alone, for tracking the joint angles' branches
  VecX<T> v_start_;              // the velocity at the start of a step (time stepping)
  SettleState<T> settle_;
  UnilateralEvents<T> gaps_;
  std::vector<int> due_;             // the sides whose event lies within the step being taken
  std::vector<double> multipliers_;  // the active sides' at its end
  int capture_ = -1;                 // the side the located event captures, or -1
  int event_ = -1;                   // the located event (UnilateralEvents' numbering)
  Carry before_;                     // the state at the start of the step being taken (events are located from it)
  bool drift_warned_ = false;
  struct PassStart {  // the start of the step being taken, for RetakeSingularPass
    VecX<T> q, v;
    IntegratorMemory integrator;
    SolverMemory solver;
  } pass_start_;
};

}  // namespace tether
