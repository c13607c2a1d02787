#include "rank_cloud_check.hpp"

#include <string>

#include "agreement.hpp"
#include "cloud_checks.hpp"

namespace pnf::mpi::detail {

void check_rank_cloud(MPI_Comm comm, const CloudView& local) {
  unsigned long long count = local.size(), first = 0;
  check_mpi(MPI_Exscan(&count, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm), "MPI_Exscan");
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) first = 0;  // MPI_Exscan leaves rank 0's undefined
  try {
    pnf::detail::check_cloud(local, pnf::detail::CloudRequirements::filter());
  } catch (const Error& e) {
    // Its vertex numbers count this rank's points; say where they start among all ranks'.
    throw Error(e.code(), std::string(e.what()) + " (its vertex 0 is vertex " + std::to_string(first) +
                              " of all ranks' points in rank order)");
  }
}

}  // namespace pnf::mpi::detail
