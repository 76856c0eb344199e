// A tether built without MuJoCo (importers/src/mjcf_unavailable.cc in place of the MJCF reader) says, for an MJCF
// model, how to get MuJoCo. Its own program: the test suite's importers have the real reader.
#include <gtest/gtest.h>

#include <string>

#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

TEST(MjcfWithoutMujoco, SaysHowToInstallIt) {
  try {
    ReadMjcf("humanoid.xml");
    ADD_FAILURE() << "read MJCF without MuJoCo";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "humanoid.xml: reading MJCF needs MuJoCo, which this build of tether was made without: install Debian's "
              "libmujoco-dev (apt-get install libmujoco-dev) and build tether again");
  }
}

}  // namespace
}  // namespace tether::importers
