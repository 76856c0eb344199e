// ReadMjcf in a build without MuJoCo (importers/CMakeLists.txt): MJCF is compiled by MuJoCo's own compiler, so
// the message says how to get it.
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {

KinematicTree ReadMjcf(const std::string& path) {
  throw InputError(path + ": reading MJCF needs MuJoCo, which this build of tether was made without: install "
                   "Debian's libmujoco-dev (apt-get install libmujoco-dev) and build tether again");
}

}  // namespace tether::importers
