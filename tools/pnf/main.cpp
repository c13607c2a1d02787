// pnf: improve the normals of point models from the command line.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "launcher.hpp"

namespace pnf::cli {

void check_output_extension(const std::string& path) { point_file_format(path); }

void check_not_overwriting_input(const std::string& in, const std::string& out, bool in_place) {
  std::error_code ec;
  if (!in_place && std::filesystem::equivalent(in, out, ec)) {
    throw Error(ErrorCode::invalid_argument, out + " is the input file; pass --in-place to overwrite it");
  }
}

}  // namespace pnf::cli

int main(int argc, char** argv) {
  using namespace pnf::cli;
  CLI::App app{"pnf: clean the normals of point models while keeping their sharp features.\n"};
  app.footer(
      "Formats (by extension): .ply, .pcd (PCL; NaN points are invalid pixels, kept in place with NaN normals; "
      "points with NaN normals are kept as they were and left out of filtering), "
      ".xyz, .xyzn, .pwn.\n"
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 input error, 4 device error, 5 output error, 6 cancelled.\n"
      "Environment: PNF_DEVICE picks the OpenCL device (cpu, gpu, accelerator, P:D, or part of a name).");
  app.require_subcommand(1);
  std::vector<Command> commands = {add_filter_command(app),  add_estimate_command(app), add_info_command(app),
                                   add_devices_command(app), add_demo_command(app),     add_render_command(app),
                                   add_compare_command(app)};
  // CLI11 would answer a mistyped command with "A subcommand is required": name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    std::string names;
    bool known = false;
    for (const Command& c : commands) {
      known = known || c.app->check_name(word);
      names += (names.empty() ? "" : ", ") + c.app->get_name();
    }
    if (!known) {
      if (launched_rank() != 0) return 0;  // under mpirun rank 0 says it and exits 2 (see below)
      std::fprintf(stderr, "pnf: '%s' is not a pnf command; the commands are %s (pnf --help)\n", word.c_str(),
                   names.c_str());
      return kUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return launched_rank() == 0 ? app.exit(e) : 0;
  } catch (const CLI::CallForAllHelp& e) {
    return launched_rank() == 0 ? app.exit(e) : 0;
  } catch (const CLI::ParseError& e) {
    // Under mpirun every rank parses the same command line: rank 0 alone says what is wrong and
    // exits 2, which becomes the job's exit code. The other ranks exit 0: had they exited 2 first,
    // mpirun would kill rank 0 before its message got out.
    if (launched_rank() != 0) return 0;
    app.exit(e);  // prints the message and a hint to use --help
    return kUsage;
  }
  for (const Command& c : commands) {
    if (c.app->parsed()) return c.run();
  }
  return kUsage;
}
