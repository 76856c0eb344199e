// A study's index (docs/reports.md): DIR/index.html beside results.csv, the figures and summary.md, with the
// summary, the results as a sortable table, the figures, and a viewer for any row whose run finished (its frames
// in DIR/views/ROW.js, written as the row is measured).
#pragma once

#include <string>
#include <vector>

#include "tether/studies/study.h"

namespace tether::cli {

// What keeps each row's motion: writes DIR/views/ROW.js (the folder made by the first row) at
// kStudyFramesPerSecond, with the row's constraint error and energy as series; a run too large for a page
// (CheckViewSize) keeps none.
RowMotion RowViewWriter(const std::string& folder);

// Writes DIR/index.html from the rows, the figures in DIR (every PNG), the best rows of summary.md and the
// views/ROW.js present; the view of a row whose run diverged, left by an earlier run of the study, is removed.
void WriteStudyIndex(const StudySpec& spec, const std::vector<StudyRow>& rows, const std::string& folder);

}  // namespace tether::cli
