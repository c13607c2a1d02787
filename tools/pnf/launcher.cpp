#include "launcher.hpp"

#include <cstdlib>
#include <initializer_list>

namespace pnf::cli {
namespace {

int environment_count(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::atoi(value) : 0;
}

}  // namespace

bool launched_as_many() {
  return environment_count("OMPI_COMM_WORLD_SIZE") > 1 || environment_count("PMI_SIZE") > 1 ||
         environment_count("SLURM_STEP_NUM_TASKS") > 1;
}

int launched_rank() {
  if (!launched_as_many()) return 0;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "SLURM_PROCID"}) {
    if (std::getenv(name)) return environment_count(name);
  }
  return 0;
}

}  // namespace pnf::cli
