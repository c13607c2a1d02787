// Collective fault agreement: before each step that others depend on, every rank says whether
// it failed, so that one rank's error ends the run on every rank with the same message instead
// of leaving the others waiting in a collective.
#pragma once

#include <mpi.h>

#include <exception>
#include <string>

#include "pnf/error.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi::detail {

// The error every rank throws once the ranks have agreed that one failed (public: pnf/mpi.hpp).
// Not checked again.
using pnf::mpi::AgreedError;

class Agreement {
 public:
  explicit Agreement(MPI_Comm comm);

  // Collective. Returns when no rank failed; otherwise throws AgreedError on every rank, with
  // the code of the lowest failing rank and the message "rank R of P: <its message>". `failure`
  // is this rank's exception, or null. An AgreedError passed in is rethrown as is (that rank
  // has agreed already).
  void check(const std::exception_ptr& failure = nullptr) const;

  // Runs `step` and then check()s, with the step's exception if it threw.
  template <typename Step>
  void run(Step&& step) const {
    std::exception_ptr failure;
    try {
      step();
    } catch (const AgreedError&) {
      throw;
    } catch (...) {
      failure = std::current_exception();
    }
    check(failure);
  }

  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

// Throws pnf::Error(device) naming `call` when an MPI call did not return MPI_SUCCESS.
void check_mpi(int result, const char* call);

}  // namespace pnf::mpi::detail
