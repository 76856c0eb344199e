// Running a matplotlib script (Debian's python3-matplotlib) for the commands that draw figures.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/model/errors.h"

namespace tether::cli {

// The drawing was ended by a signal: a Ctrl-C reaches the whole foreground process group, python too, while
// tether itself waits with the signal ignored (std::system). The figures are the last output, so everything
// else was written; main ends the process as the signal would.
class DrawingInterrupted : public RunInterrupted {
 public:
  using RunInterrupted::RunInterrupted;
};

// Writes `script` to a temporary file and runs it with `args` under /usr/bin/python3 (python3 from PATH if that
// is missing). Throws InputError naming `flag` with python's last error line when it fails, DrawingInterrupted
// when a signal ended it.
void RunMatplotlib(const std::string& script, const std::vector<std::string>& args, const std::string& flag);

}  // namespace tether::cli
