// Temporary folders and runs of the tether executable, for the tests that touch files or the command line.
#pragma once

#include <string>
#include <vector>

namespace tether::testing {

std::string ReadText(const std::string& path);
// The lines of a text, without their line ends.
std::vector<std::string> Lines(const std::string& text);
// The comma-separated cells of one CSV line, quoted cells unquoted (a trailing empty cell is dropped).
std::vector<std::string> CsvCells(const std::string& line);

// A fresh folder under GoogleTest's temporary directory, removed with everything in it at the end.
class TempFolder {
 public:
  explicit TempFolder(const std::string& prefix = "tether_test");
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::string& path() const { return path_; }
  std::string Path(const std::string& name) const { return path_ + "/" + name; }
  // Writes a file in the folder and returns its path.
  std::string Write(const std::string& name, const std::string& text) const;
  // The names in the folder, "." and ".." aside.
  std::vector<std::string> Entries() const;

 private:
  std::string path_;
};

struct Outcome {
  int status = -1;  // the exit status, or -1 when the process was killed by a signal (a crash)
  std::string out, err;
};

// Runs `LAUNCHER tether ARGS` (both reach the shell as written; the launcher is e.g. mpirun with its flags),
// capturing stdout and stderr through files in `folder`.
Outcome RunTether(const std::string& args, const TempFolder& folder, const std::string& launcher = "");

}  // namespace tether::testing
