// Which one-sided rows (law kGap, constraint_rows.h) are active: the second of the two solves behind the KKT
// system, beside SchurSolver's solve of a fixed set of rows, which it calls. From a set of candidate rows it
// solves the equality system with all of them, leaves out the row whose push is the most negative (a row that
// would pull) and solves again, until no row pulls: a primal active-set method on the Schur complement of the
// active rows. Each pass leaves out one row, so it ends within as many passes as there are candidates, and every
// solve is the exact KKT solve of its rows, not an iteration to a tolerance (projected Gauss-Seidel's), so the
// motion keeps its integrator's order and its derivatives are the implicit function theorem's. Unlike Lemke's
// method it never lets a left-out row back in: exact for one row, and for rows that do not share a body; where
// coupled rows leave one out whose gap then closes, that gap is the next event the stepper locates. Joint limits use it
// for an impact's impulses and for the rows held at rest (unilateral_events.h).
#pragma once

#include <cstddef>
#include <vector>

namespace tether {

// `pushes(set, &rows, &push)` solves with the rows `set` marks (a flag per row) and gives each of them (`rows`,
// indices into `set`) its push, >= 0 where the row holds; false when the solve fails. A row marked in `kept` is
// never left out; a push of exactly zero is left out too when `release_at_zero`. Returns false when a solve
// failed (`set` as it was solved then), true with `set` the active rows.
template <typename Pushes>
bool SolveActiveSet(std::vector<char>* set, const std::vector<char>& kept, bool release_at_zero, Pushes pushes) {
  std::vector<int> rows;
  std::vector<double> push;
  for (std::size_t pass = 0; pass <= set->size(); ++pass) {
    if (!pushes(*set, &rows, &push)) return false;
    int weakest = -1;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!kept[rows[k]] && (weakest < 0 || push[k] < push[weakest])) weakest = static_cast<int>(k);
    }
    if (weakest < 0 || push[weakest] > 0.0 || (push[weakest] == 0.0 && !release_at_zero)) return true;
    (*set)[rows[weakest]] = 0;
  }
  return true;
}

}  // namespace tether
