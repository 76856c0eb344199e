// A study spread over MPI ranks: `mpirun -n K tether study STUDY.json --out DIR`.
//
// Rank 0 takes up the rows an interrupted run finished (results.partial.csv) and broadcasts the unfinished ones;
// rank r runs the rows at positions r, r + K, r + 2K, ... of that list on its own threads; every finished row is
// sent to rank 0, which logs it, reports progress and writes DIR/results.csv: the same file a single-process
// run writes, since rows are measured alone and written in row order. Every rank reads STUDY.json and its scenes
// itself, so on several machines they must see the same files; only rank 0 writes.
//
// MPI is an optional build feature (CMake option TETHER_MPI, on when Debian's libopenmpi-dev is found). Without
// it, MpiSession's constructor throws InputError saying how to get it.
#pragma once

#include <string>
#include <vector>

#include "tether/studies/study.h"

namespace tether {

// True when this process was started by mpirun (Open MPI, MPICH and PMIx set these variables).
bool LaunchedByMpirun();

// MPI_Init_thread (only the calling thread talks to MPI) and, on destruction, MPI_Finalize.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // This machine's cores divided among the ranks running on it (at least 1).
  int threads_per_rank() const { return threads_per_rank_; }

 private:
  int rank_ = 0, size_ = 1, threads_per_rank_ = 1;
};

// Runs (or resumes) the study over the session's ranks, each on `threads` threads. Returns the rows on rank 0
// (which writes folder/results.csv and calls `progress`), nothing on the other ranks. A failure on any rank
// other than a diverged row (which is a result) prints its message and aborts every rank (MPI_Abort, status 1).
std::vector<StudyRow> RunStudyOverMpi(const MpiSession& session, const StudySpec& spec, const std::string& folder,
                                      int threads, bool restart, const StudyProgress& progress,
                                      const RowMotion& motion = {});

}  // namespace tether
