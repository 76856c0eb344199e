#include "tether/studies/study_mpi.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <thread>

#include "results_folder.h"
#include "row_runner.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

constexpr int kRowTag = 1;

// A finished row travels as its text "INDEX,<line>".
void SendRow(const FinishedRow& row) {
  const std::string text = std::to_string(row.index) + "," + row.line;
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kRowTag, MPI_COMM_WORLD);
}

FinishedRow ReceiveRow() {
  MPI_Status status;
  MPI_Probe(MPI_ANY_SOURCE, kRowTag, MPI_COMM_WORLD, &status);
  int length = 0;
  MPI_Get_count(&status, MPI_CHAR, &length);
  std::string text(length, '\0');
  MPI_Recv(text.data(), length, MPI_CHAR, status.MPI_SOURCE, kRowTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  const size_t comma = text.find(',');
  return {std::atoi(text.substr(0, comma).c_str()), text.substr(comma + 1)};
}

bool RowWaiting() {
  int waiting = 0;
  MPI_Iprobe(MPI_ANY_SOURCE, kRowTag, MPI_COMM_WORLD, &waiting, MPI_STATUS_IGNORE);
  return waiting != 0;
}

// Rank 0's list of unfinished rows, on every rank.
std::vector<int> BroadcastRows(std::vector<int> rows) {
  int count = static_cast<int>(rows.size());
  MPI_Bcast(&count, 1, MPI_INT, 0, MPI_COMM_WORLD);
  rows.resize(count);
  MPI_Bcast(rows.data(), count, MPI_INT, 0, MPI_COMM_WORLD);
  return rows;
}

std::vector<int> ShareOf(const std::vector<int>& rows, int rank, int ranks) {
  std::vector<int> share;
  for (size_t k = rank; k < rows.size(); k += ranks) share.push_back(rows[k]);
  return share;
}

}  // namespace

MpiSession::MpiSession() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int ranks_here = 1;
  MPI_Comm_size(node, &ranks_here);
  MPI_Comm_free(&node);
  threads_per_rank_ = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / ranks_here);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

std::vector<StudyRow> RunStudyOverMpi(const MpiSession& session, const StudySpec& spec, const std::string& folder,
                                      int threads, bool restart, const StudyProgress& progress,
                                      const RowMotion& motion) {
  try {
    if (session.rank() != 0) {
      const std::vector<int> rows = BroadcastRows({});
      RunRows(
          spec, ShareOf(rows, session.rank(), session.size()), threads, SendRow, [] {}, motion);
      return {};
    }
    ResultsFolder results(spec, folder, restart, progress);
    const std::vector<int> rows = BroadcastRows(results.Unfinished());
    const std::vector<int> own = ShareOf(rows, 0, session.size());
    size_t remote = rows.size() - own.size();
    auto receive_waiting = [&] {
      for (; remote > 0 && RowWaiting(); --remote) results.Record(ReceiveRow());
    };
    RunRows(
        spec, own, threads, [&](const FinishedRow& row) { results.Record(row); }, receive_waiting, motion);
    for (; remote > 0; --remote) results.Record(ReceiveRow());
    return results.Finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tether: rank %d: %s\n", session.rank(), e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
    return {};
  }
}

}  // namespace tether
