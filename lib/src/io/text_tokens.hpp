// Splitting a line of a text file (ascii PLY, .xyz) into whitespace-separated tokens.
#pragma once

#include <string_view>
#include <vector>

namespace pnf {

inline bool is_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Replaces `tokens` with the tokens of `line`; they point into `line`.
inline void split_tokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank_char(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !is_blank_char(line[i])) ++i;
    if (i > begin) tokens.push_back(line.substr(begin, i - begin));
  }
}

}  // namespace pnf
