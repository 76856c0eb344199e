#include "tether/studies/study.h"

#include "results_folder.h"
#include "row_runner.h"

namespace tether {

std::vector<StudyRow> RunStudy(const StudySpec& spec, const std::string& folder, int threads, bool restart,
                               const StudyProgress& progress, const RowMotion& motion) {
  ResultsFolder results(spec, folder, restart, progress);
  if (results.Done()) return results.Finish();
  RunRows(
      spec, results.Unfinished(), threads, [&](const FinishedRow& row) { results.Record(row); }, [] {}, motion);
  return results.Finish();
}

}  // namespace tether
