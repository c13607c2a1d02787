// expect_error: a call must throw pnf::Error with this code and a message that mentions each of
// `needles` (what and where, as the brief asks of every error).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "pnf/error.hpp"

namespace pnf::test {

template <class Code>
inline void expect_error(const std::function<void()>& call, ErrorCode code, const Code& needles) {
  try {
    call();
    ADD_FAILURE() << "no pnf::Error thrown";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), code) << error.what();
    for (const std::string& needle : needles) {
      EXPECT_NE(std::string(error.what()).find(needle), std::string::npos)
          << "'" << error.what() << "' does not mention '" << needle << "'";
    }
  }
}

}  // namespace pnf::test
