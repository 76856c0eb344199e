// Output files that are complete or absent, and never written over an input.
//
// AtomicOutputFile: the output appears at `path` only when Commit() is called. A regular file (or a new one) is
// written to a temporary file beside it ("PATH.partial.PID", removed on SIGINT/SIGTERM/SIGHUP: interrupts.h)
// and renamed over it, so a failed or interrupted run leaves no partial output and the old file stays whole. A
// symbolic link is followed: its target is replaced and the link stays. Anything else that exists (a device such
// as /dev/null, a FIFO) is written through directly.
//
// Errors: a path that cannot be written (a missing folder, no permission, a folder, a dangling link) is an
// InputError when the file is opened; a write that fails on the way (a full disk) an OutputError at Commit().
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "tether/dynamics/integration/interrupts.h"

namespace tether {

class AtomicOutputFile {
 public:
  explicit AtomicOutputFile(const std::string& path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::ostream& stream() { return stream_; }
  void Commit();

 private:
  std::string path_;       // as given, for messages
  std::string target_;     // the file that ends up written (a link's target)
  std::string temporary_;  // empty when writing through
  std::unique_ptr<TemporaryPath> registered_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Refuses, before any work, an output path given with `flag` that is one of the run's `inputs` (the same file,
// through any link), a folder, or in a folder that does not exist or cannot be written: InputError naming the
// flag.
void CheckOutputPath(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag);

}  // namespace tether
