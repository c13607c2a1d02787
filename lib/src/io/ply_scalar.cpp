#include "ply_scalar.hpp"

#include <charconv>
#include <cstring>
#include <limits>
#include <type_traits>

namespace pnf {
namespace {

constexpr bool kHostIsBigEndian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;

template <typename T>
T load(const unsigned char* bytes) {
  unsigned char copy[sizeof(T)];
  std::memcpy(copy, bytes, sizeof(T));
  if (kHostIsBigEndian) reverse_bytes(copy, sizeof(T));
  T value;
  std::memcpy(&value, copy, sizeof(T));
  return value;
}

template <typename T>
void store(T value, unsigned char* bytes) {
  std::memcpy(bytes, &value, sizeof(T));
  if (kHostIsBigEndian) reverse_bytes(bytes, sizeof(T));
}

// Calls f(T{}) with T the C++ type of `type`.
template <typename F>
decltype(auto) visit_scalar(PlyScalar type, F&& f) {
  switch (type) {
    case PlyScalar::int8: return f(std::int8_t{});
    case PlyScalar::uint8: return f(std::uint8_t{});
    case PlyScalar::int16: return f(std::int16_t{});
    case PlyScalar::uint16: return f(std::uint16_t{});
    case PlyScalar::int32: return f(std::int32_t{});
    case PlyScalar::uint32: return f(std::uint32_t{});
    case PlyScalar::float32: return f(float{});
    case PlyScalar::int64: return f(std::int64_t{});
    case PlyScalar::uint64: return f(std::uint64_t{});
    case PlyScalar::float64: break;
  }
  return f(double{});
}

struct ScalarName {
  const char* name;
  PlyScalar type;
};

// The original PLY names first, so that scalar_name returns them; then the sized aliases.
constexpr ScalarName kScalarNames[] = {
    {"char", PlyScalar::int8},       {"uchar", PlyScalar::uint8},    {"short", PlyScalar::int16},
    {"ushort", PlyScalar::uint16},   {"int", PlyScalar::int32},      {"uint", PlyScalar::uint32},
    {"float", PlyScalar::float32},   {"double", PlyScalar::float64}, {"int8", PlyScalar::int8},
    {"uint8", PlyScalar::uint8},     {"int16", PlyScalar::int16},    {"uint16", PlyScalar::uint16},
    {"int32", PlyScalar::int32},     {"uint32", PlyScalar::uint32},  {"float32", PlyScalar::float32},
    {"float64", PlyScalar::float64},
};

template <typename T>
bool parse_integer(std::string_view token, unsigned char* bytes, std::string& why) {
  // from_chars takes no '+'; PLY writers rarely emit one, but it is a valid integer.
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  if constexpr (sizeof(T) == 8) {
    // 64-bit values (PCD only) are parsed in their own type: int64 cannot hold every uint64.
    T value = 0;
    const auto result = std::from_chars(token.data(), end, value);
    const bool negative_unsigned = std::is_unsigned_v<T> && !token.empty() && token[0] == '-';
    if (result.ec == std::errc::result_out_of_range || negative_unsigned) {
      why = "out of range";
      return false;
    }
    if (result.ec != std::errc() || result.ptr != end) {
      why = "not an integer";
      return false;
    }
    store(value, bytes);
    return true;
  } else {
    std::int64_t value = 0;
    const auto result = std::from_chars(token.data(), end, value);
    if (result.ec == std::errc::invalid_argument || result.ptr != end) {
      why = "not an integer";
      return false;
    }
    if (result.ec == std::errc::result_out_of_range || value < std::numeric_limits<T>::min() ||
        value > static_cast<std::int64_t>(std::numeric_limits<T>::max())) {
      why = "out of range";
      return false;
    }
    store(static_cast<T>(value), bytes);
    return true;
  }
}

template <typename T>
bool parse_real(std::string_view token, unsigned char* bytes, std::string& why) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  T value = 0;
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  if (result.ec == std::errc::invalid_argument || result.ptr != end) {
    why = "not a number";
    return false;
  }
  if (result.ec == std::errc::result_out_of_range) {
    // Overflow to infinity or underflow to zero: either would silently change the value.
    why = "out of range";
    return false;
  }
  store(value, bytes);
  return true;
}

}  // namespace

std::size_t scalar_size(PlyScalar type) {
  return visit_scalar(type, [](auto value) { return sizeof(value); });
}

bool parse_scalar_name(std::string_view name, PlyScalar& type) {
  for (const ScalarName& entry : kScalarNames) {
    if (name == entry.name) {
      type = entry.type;
      return true;
    }
  }
  return false;
}

const char* scalar_name(PlyScalar type) {
  // Not in kScalarNames: PLY headers must not accept them.
  if (type == PlyScalar::int64) return "int64";
  if (type == PlyScalar::uint64) return "uint64";
  for (const ScalarName& entry : kScalarNames) {
    if (entry.type == type) return entry.name;
  }
  return "double";
}

bool is_integer(PlyScalar type) { return type != PlyScalar::float32 && type != PlyScalar::float64; }

void reverse_bytes(unsigned char* value, std::size_t size) {
  for (std::size_t i = 0; i < size / 2; ++i) std::swap(value[i], value[size - 1 - i]);
}

double load_as_double(PlyScalar type, const unsigned char* bytes) {
  return visit_scalar(type, [bytes](auto value) { return static_cast<double>(load<decltype(value)>(bytes)); });
}

void store_real(PlyScalar type, double value, unsigned char* bytes) {
  if (type == PlyScalar::float32) {
    store(static_cast<float>(value), bytes);
  } else {
    store(value, bytes);
  }
}

bool load_count(PlyScalar count_type, const unsigned char* bytes, std::uint64_t& count) {
  const double value = load_as_double(count_type, bytes);
  if (value < 0) return false;
  count = static_cast<std::uint64_t>(value);
  return true;
}

bool parse_token(PlyScalar type, std::string_view token, unsigned char* bytes, std::string& why) {
  return visit_scalar(type, [&](auto value) {
    using T = decltype(value);
    if constexpr (std::is_integral_v<T>) {
      return parse_integer<T>(token, bytes, why);
    } else {
      return parse_real<T>(token, bytes, why);
    }
  });
}

void append_token(PlyScalar type, const unsigned char* bytes, std::string& out) {
  // 32 characters hold any shortest float or double, and any 64-bit integer.
  char buffer[32];
  const auto result = visit_scalar(type, [&](auto value) {
    using T = decltype(value);
    const T loaded = load<T>(bytes);
    if constexpr (std::is_same_v<T, std::uint64_t>) {
      return std::to_chars(buffer, buffer + sizeof buffer, loaded);
    } else if constexpr (std::is_integral_v<T>) {
      return std::to_chars(buffer, buffer + sizeof buffer, static_cast<std::int64_t>(loaded));
    } else {
      return std::to_chars(buffer, buffer + sizeof buffer, loaded);
    }
  });
  out.append(buffer, result.ptr);
}

}  // namespace pnf
