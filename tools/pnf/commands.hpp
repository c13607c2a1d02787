// The subcommands of pnf; each file cmd_<name>.cpp registers one.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace pnf::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  // returns the exit code
};

Command add_filter_command(CLI::App& parent);
Command add_devices_command(CLI::App& parent);
Command add_info_command(CLI::App& parent);
Command add_estimate_command(CLI::App& parent);
Command add_demo_command(CLI::App& parent);

// Throws pnf::Error(invalid_argument) when `path` does not end in a format pnf can write,
// so a run fails before the work rather than after it.
void check_output_extension(const std::string& path);

// Throws pnf::Error(invalid_argument) when `out` names the same file as `in` and `in_place` is
// false: the input is never overwritten unless asked.
void check_not_overwriting_input(const std::string& in, const std::string& out, bool in_place);

}  // namespace pnf::cli
