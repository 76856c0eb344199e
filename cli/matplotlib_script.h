// Running a matplotlib script (Debian's python3-matplotlib) for the commands that draw figures.
#pragma once

#include <string>
#include <vector>

namespace tether::cli {

// Writes `script` to a temporary file and runs it with `args` under /usr/bin/python3 (python3 from PATH if that
// is missing). Throws InputError naming `flag` with python's last error line when it fails.
void RunMatplotlib(const std::string& script, const std::vector<std::string>& args, const std::string& flag);

}  // namespace tether::cli
