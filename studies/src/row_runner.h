// Running the rows of a study: measuring one row, and a pool of threads that runs a list of rows and hands each
// finished row, as one results.csv line, to the calling thread (so that only that thread writes files or talks
// to MPI).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tether/studies/study.h"

namespace tether {

// A finished row: its index and its results.csv line (swept values, metrics, status).
struct FinishedRow {
  int index = 0;
  std::string line;
};

// The expected cost of row `index` relative to the others, for the time a study has left: its number of steps
// times the derivative evaluations per step (1 for euler and symplectic_euler, 4 for rk4, about 7 for rk45).
double RowCost(const StudySpec& spec, int index);

// Runs rows `indices` of the study on `threads` threads. `on_row` is called on the calling thread for each
// finished row, in the order they finish; `idle` is called on the calling thread about every 10 ms while it waits.
// A row that throws (other than a diverged simulation, which is a row's result) ends the run: the exception is
// rethrown here once the running rows have finished. An interruption (Interrupted(), interrupts.h) ends it too:
// no row starts after it, the rows under way are finished and handed on, and StudyInterrupted is thrown.
// `motion` (may be empty) is given each finished run (study.h's RowMotion).
void RunRows(const StudySpec& spec, const std::vector<int>& indices, int threads,
             const std::function<void(const FinishedRow&)>& on_row, const std::function<void()>& idle,
             const RowMotion& motion);

}  // namespace tether
