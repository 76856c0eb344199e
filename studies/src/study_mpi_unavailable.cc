// study_mpi.h for a build without MPI (TETHER_MPI off or libopenmpi-dev missing).
#include "tether/dynamics/model/errors.h"
#include "tether/studies/study_mpi.h"

namespace tether {

MpiSession::MpiSession() {
  throw InputError(
      "this tether was built without MPI, so mpirun cannot spread a study over ranks: install libopenmpi-dev "
      "openmpi-bin and rebuild (CMake option TETHER_MPI), or run the study without mpirun (it uses every core)");
}

MpiSession::~MpiSession() = default;

std::vector<StudyRow> RunStudyOverMpi(const MpiSession&, const StudySpec&, const std::string&, int, bool,
                                      const StudyProgress&, const RowMotion&) {
  return {};
}

}  // namespace tether
