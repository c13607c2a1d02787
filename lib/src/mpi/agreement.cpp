#include "agreement.hpp"

#include <vector>

namespace pnf::mpi::detail {

void check_mpi(int result, const char* call) {
  if (result == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(result, text, &length);
  throw Error(ErrorCode::device, std::string(call) + " failed: " + std::string(text, std::size_t(length)));
}

Agreement::Agreement(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

void Agreement::check(const std::exception_ptr& failure) const {
  int code = int(ErrorCode::device);
  std::string message;
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const AgreedError&) {
      throw;
    } catch (const Error& e) {
      code = int(e.code());
      message = e.what();
    } catch (const std::bad_alloc&) {
      message = "out of memory";
    } catch (const std::exception& e) {
      message = e.what();
    }
  }
  int first = failure ? rank_ : size_;
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
  if (first == size_) return;
  // The first failing rank's code and message go to every rank.
  int length = int(message.size());
  int header[2] = {code, length};
  MPI_Bcast(header, 2, MPI_INT, first, comm_);
  message.resize(std::size_t(header[1]));
  MPI_Bcast(message.data(), header[1], MPI_CHAR, first, comm_);
  throw AgreedError(ErrorCode(header[0]),
                    "rank " + std::to_string(first) + " of " + std::to_string(size_) + ": " + message);
}

}  // namespace pnf::mpi::detail
