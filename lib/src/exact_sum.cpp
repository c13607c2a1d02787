// The exact sum of doubles (exact_sum.hpp).
#include "exact_sum.hpp"

#include <cmath>

namespace pnf::detail {
namespace {

constexpr int kDigitBits = 32;
constexpr std::int64_t kDigitBase = std::int64_t(1) << kDigitBits;
constexpr int kLowestExponent = -1074;  // every finite double is an integer times 2^-1074
// A digit takes up to 2^32 from one value; carried every 2^30 values, none passes 2^62.
constexpr std::size_t kValuesBetweenCarries = std::size_t(1) << 30;

}  // namespace

void ExactSum::add(double value) {
  if (value == 0 || !std::isfinite(value)) return;
  int exponent = 0;
  const double fraction = std::frexp(std::fabs(value), &exponent);  // [0.5, 1) x 2^exponent
  // |value| = mantissa x 2^(bit - 1074), the mantissa an integer of at most 53 bits.
  std::uint64_t mantissa = std::uint64_t(std::ldexp(fraction, 53));
  int bit = exponent - 53 - kLowestExponent;
  if (bit < 0) {  // subnormal: the bits shifted out are zeros
    mantissa >>= -bit;
    bit = 0;
  }
  const int digit = bit / kDigitBits;
  unsigned __int128 shifted = static_cast<unsigned __int128>(mantissa) << (bit % kDigitBits);
  const std::int64_t sign = value < 0 ? -1 : 1;
  for (int d = digit; shifted != 0; ++d) {
    digits_[std::size_t(d)] += sign * std::int64_t(shifted & (kDigitBase - 1));
    shifted >>= kDigitBits;
  }
  if (++uncarried_ == kValuesBetweenCarries) carry();
}

void ExactSum::add(const ExactSum& other) {
  ExactSum carried = other;
  carried.carry();
  carry();
  for (int d = 0; d < kDigits; ++d) digits_[std::size_t(d)] += carried.digits_[std::size_t(d)];
  carry();
}

void ExactSum::carry() {
  for (int d = 0; d + 1 < kDigits; ++d) {
    // Floor division by 2^32, negative digits included.
    const std::int64_t over =
        (digits_[std::size_t(d)] - ((digits_[std::size_t(d)] % kDigitBase + kDigitBase) % kDigitBase)) / kDigitBase;
    digits_[std::size_t(d)] -= over * kDigitBase;
    digits_[std::size_t(d) + 1] += over;
  }
  uncarried_ = 0;
}

std::array<std::int64_t, ExactSum::kDigits>& ExactSum::carried_digits() {
  carry();
  return digits_;
}

double ExactSum::value() const {
  ExactSum carried = *this;
  carried.carry();
  // A negative sum carries a -1 into the top digit, beyond the doubles' range: sum the magnitude.
  const bool negative = carried.digits_.back() < 0;
  if (negative) {
    for (std::int64_t& digit : carried.digits_) digit = -digit;
    carried.carry();
  }
  // From the top digit down: the carried digits are the magnitude's one representation, so the
  // roundings of this loop are the same for the same sum.
  double sum = 0;
  for (int d = kDigits - 1; d >= 0; --d) {
    sum += std::ldexp(double(carried.digits_[std::size_t(d)]), d * kDigitBits + kLowestExponent);
  }
  return negative ? -sum : sum;
}

}  // namespace pnf::detail
