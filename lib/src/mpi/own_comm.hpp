// A duplicate of the caller's communicator for the library's collectives, so that no message of
// ours meets one of theirs.
#pragma once

#include <mpi.h>

namespace pnf::mpi::detail {

class OwnComm {
 public:
  explicit OwnComm(MPI_Comm comm) { MPI_Comm_dup(comm, &comm_); }
  ~OwnComm() { MPI_Comm_free(&comm_); }
  OwnComm(const OwnComm&) = delete;
  OwnComm& operator=(const OwnComm&) = delete;
  MPI_Comm get() const { return comm_; }

 private:
  MPI_Comm comm_;
};

}  // namespace pnf::mpi::detail
