#include "matplotlib_script.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tether/dynamics/errors.h"
#include "tether/dynamics/interrupts.h"

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
  std::ofstream(work / "script.py") << script;
  const char* python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string command = std::string(python) + " " + Quote((work / "script.py").string());
  for (const std::string& a : args) command += " " + Quote(a);
  command += " 2>" + Quote((work / "errors.txt").string());
  const int status = std::system(command.c_str());
  std::string errors;
  std::getline(std::ifstream(work / "errors.txt"), errors, '\0');
  fs::remove_all(work);
  if (status != 0) {
    while (!errors.empty() && errors.back() == '\n') errors.pop_back();
    throw InputError(flag + ": drawing failed (python3 with matplotlib is needed: apt-get install python3-matplotlib)" +
                     (errors.empty() ? std::string() : ": " + errors.substr(errors.rfind('\n') + 1)));
  }
}

}  // namespace tether::cli
