#include "matplotlib_script.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/model/errors.h"

namespace tether::cli {
namespace {

std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void RunMatplotlib(const std::string& script, const std::vector<std::string>& args, const std::string& flag) {
  namespace fs = std::filesystem;
  char pattern[] = "/tmp/tether-plot-XXXXXX";
  if (!mkdtemp(pattern)) throw InputError(flag + ": cannot make a temporary folder");
  const fs::path work(pattern);
  const TemporaryPath folder(work.string()), script_file((work / "script.py").string()),
      error_file((work / "errors.txt").string());  // removed if the process is interrupted meanwhile
  // A signal ends python as it would any program (its default action), not as a KeyboardInterrupt: raised inside
  // an import, numpy turns that into an ImportError, which read as a missing matplotlib (a Ctrl-C while a study
  // started drawing)
  std::ofstream(work / "script.py") << "import signal\n"
                                       "for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):\n"
                                       "    signal.signal(s, signal.SIG_DFL)\n"
                                    << script;
  const char* python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string command = std::string(python) + " " + Quote((work / "script.py").string());
  for (const std::string& a : args) command += " " + Quote(a);
  command += " 2>" + Quote((work / "errors.txt").string());
  const int status = std::system(command.c_str());
  std::string errors;
  std::getline(std::ifstream(work / "errors.txt"), errors, '\0');
  fs::remove_all(work);
  while (!errors.empty() && errors.back() == '\n') errors.pop_back();
  const std::string last_error = errors.substr(errors.rfind('\n') + 1);
  // killed by a signal: the shell itself, or python under it (the shell then exits with 128 + the signal), or,
  // before the script's first line restores the default action, python's own KeyboardInterrupt
  const int signal = WIFSIGNALED(status)                                ? WTERMSIG(status)
                     : WIFEXITED(status) && WEXITSTATUS(status) > 128   ? WEXITSTATUS(status) - 128
                     : status != 0 && last_error == "KeyboardInterrupt" ? SIGINT
                                                                        : 0;
  if (signal == SIGINT || signal == SIGTERM || signal == SIGHUP) throw DrawingInterrupted(signal);
  if (status != 0) {
    throw InputError(flag + ": drawing failed (python3 with matplotlib is needed: apt-get install python3-matplotlib)" +
                     (errors.empty() ? std::string() : ": " + last_error));
  }
}

}  // namespace tether::cli
