// The exact sum of doubles, whatever their order and however they are grouped (one process's
// rows, or each rank's part added up across ranks): the mean of the `radius` property is the same
// bits in any row order and on any number of ranks.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace pnf::detail {

// A fixed-point number spanning every finite double (2^-1074 up to 2^1024) in 32-bit digits held
// in 64-bit integers: each value added is split into the digits it covers, exactly, and digits add
// as integers, so the digits after any sequence of additions depend only on the values added.
class ExactSum {
 public:
  static constexpr int kDigits = 68;
  void add(double value);  // finite values only: a NaN or infinity is not added
  void add(const ExactSum& other);
  // The sum, rounded to a double by a fixed rule (to within an ulp of the exact sum): the same
  // bits for the same multiset of values.
  double value() const;
  // The digits, carried so that each is in [0, 2^32) but the top one: for MPI_Allreduce with
  // MPI_INT64_T and MPI_SUM (a part's digits carried, the sums of up to 2^31 parts cannot
  // overflow), after which value() of the reduced digits is the whole's.
  std::array<std::int64_t, kDigits>& carried_digits();

 private:
  void carry();
  std::array<std::int64_t, kDigits> digits_{};
  std::size_t uncarried_ = 0;  // values added since the last carry
};

}  // namespace pnf::detail
