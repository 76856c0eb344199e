// libFuzzer target for `tether import`: the bytes of a model file go through ImportModel, the importer's entry
// point, as a URDF (urdf_import_fuzzer, urdfdom's parser) or an MJCF (mjcf_import_fuzzer, MuJoCo's compiler),
// by the file's extension as the command line reads it (TETHER_FUZZ_EXTENSION).
//
// What may happen: the model imports, and its scene is one the scene format accepts (ImportModel promises it),
// or an InputError is thrown whose message starts with the file's path. Anything else is a finding: another
// exception, a crash, a sanitizer report in tether's code, or an imported scene that ParseScene refuses.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace {

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "model_import_fuzzer: %s\n", what.c_str());
  std::abort();
}

std::string* path = nullptr;

void Cleanup() { std::remove(path->c_str()); }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* folder = std::getenv("TMPDIR");
  path = new std::string(std::string(folder && *folder ? folder : "/tmp") + "/tether_fuzz_" + std::to_string(getpid()) +
                         TETHER_FUZZ_EXTENSION);
  std::atexit(Cleanup);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::FILE* file = std::fopen(path->c_str(), "wb");
  if (!file || std::fwrite(data, 1, size, file) != size || std::fclose(file) != 0) Finding("cannot write " + *path);
  try {
    const tether::importers::ImportedScene imported = tether::importers::ImportModel(*path, {});
    try {
      tether::ParseScene(tether::ParseJsonText(imported.scene.dump(), "imported"), "imported");
    } catch (const tether::InputError& e) {
      Finding(std::string("an imported scene the scene format refuses: ") + e.what());
    }
  } catch (const tether::InputError& e) {
    const std::string message = e.what();
    // the importer's own check of its scene names the model as "PATH (imported)"
    if (message.rfind(*path + ": ", 0) != 0 && message.rfind(*path + " (imported): ", 0) != 0) {
      Finding("an input error that does not name the file: " + message);
    }
  }
  return 0;
}
