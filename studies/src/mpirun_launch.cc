#include <cstdlib>

#include "tether/studies/study_mpi.h"

namespace tether {

bool LaunchedByMpirun() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(variable)) return true;
  }
  return false;
}

}  // namespace tether
