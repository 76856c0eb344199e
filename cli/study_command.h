// `tether study STUDY.json --out DIR [--threads N]`: runs (or resumes) a study, with a progress bar and an
// estimate of the time left on stderr, and writes DIR/results.csv, one figure per metric (PNG and SVG) and
// DIR/summary.md (studies/include/tether/studies/study.h).
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeStudyCommand(CLI::App* parent);

}  // namespace tether::cli
