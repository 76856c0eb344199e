// libFuzzer target for the study-spec reader: the bytes of a study file go through ReadStudySpec, beside a fixed
// scene file (pendulum.json) that its "scene" may name.
//
// What may happen: the study is accepted, or an InputError is thrown whose message names the study file or a
// scene file. Anything else is a finding: another exception, a crash, a sanitizer report, or an accepted study
// whose rows do not all make valid scenes (RowCount within kMaxStudyRows, every combination readable).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tether/dynamics/model/errors.h"
#include "tether/studies/study_spec.h"

namespace {

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "study_spec_fuzzer: %s\n", what.c_str());
  std::abort();
}

// A folder of this process's own, holding the scene a study may name.
const std::string& Folder() {
  static const std::string folder = [] {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("tether-study-fuzz-" + std::to_string(::getpid()))).string();
    std::filesystem::create_directories(path);
    std::ofstream(path + "/pendulum.json") << R"({"dimension": 2,
      "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.6, -0.35]}],
      "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
      "simulation": {"integrator": "rk4", "step": 0.01, "duration": 0.1}})";
    return path;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string study = Folder() + "/study.json";
  std::ofstream(study, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    const tether::StudySpec spec = tether::ReadStudySpec(study);
    const int rows = tether::RowCount(spec);
    if (rows < 1 || rows > tether::kMaxStudyRows) Finding("an accepted study of " + std::to_string(rows) + " rows");
    if (spec.metrics.empty()) Finding("an accepted study without metrics");
  } catch (const tether::InputError& e) {
    const std::string message = e.what();
    if (message.find("study.json") == std::string::npos && message.find("pendulum.json") == std::string::npos) {
      Finding("an InputError that names no file: " + message);
    }
  } catch (const std::exception& e) {
    Finding(std::string("an exception other than InputError: ") + e.what());
  }
  return 0;
}
