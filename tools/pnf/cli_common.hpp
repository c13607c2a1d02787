// What every pnf subcommand shares: exit codes, error reporting, the progress display.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

#include "pnf/choose_filter_params.hpp"
#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/point_file.hpp"

namespace pnf::cli {

// Exit codes, documented in the README and in `pnf --help`.
enum ExitCode {
  kOk = 0,
  kInternal = 1,   // a bug: an unexpected exception
  kUsage = 2,      // bad command line or parameter value
  kInput = 3,      // the input file is missing, unreadable or malformed, or its data is unusable
  kDevice = 4,     // no OpenCL platform or device, kernel build or run failure
  kOutput = 5,     // the output could not be written (nothing is left behind)
  kCancelled = 6,  // interrupted
};

// Where a pnf::Error happened, for the exit code of io errors (reading vs writing).
enum class Stage { reading, running, writing };

// Prints "pnf: error: <message>" to stderr and returns the exit code for `e` at `stage`.
int report(const Error& e, Stage stage);
// The exit code for `e` at `stage`, printing nothing.
int exit_code(const Error& e, Stage stage);

// A progress callback that, unless `quiet`, draws a one-line bar on stderr when stderr is a
// terminal (the neighbour lists, each pass, estimate_normals' and --auto's stages), and otherwise
// (a batch log; rank 0 under mpirun) writes a line "pnf: pass 3/8, 40% of the passes (12.3 s)" at
// most every 10 s, none in a shorter run (ProgressLines). Making it installs a SIGINT / SIGTERM
// handler: after the first such signal the callback returns false, so the run stops at its next
// report (after the current pass, or within about 0.2 s while lists are built or normals estimated)
// with Error(cancelled) (exit kCancelled, nothing written); a second signal ends the process at
// once.
ProgressCallback progress_bar(bool quiet);

// Runs `body`, turning pnf::Error into a message and exit code (stage from `stage`, which body
// updates as it goes) and anything else into kInternal.
int guarded(Stage& stage, const std::function<int()>& body);

// The device / backend flags shared by filter, devices and demo.
struct DeviceFlags {
  std::string device;
  std::string backend = "opencl";
  void add_to(CLI::App& app, bool with_backend = true);
  FilterOptions options() const;
};

// A check for a value that must be a finite number > 0 ("--radius: must be finite and > 0, got
// 0"): CLI11's PositiveNumber would print its range up to DBL_MAX in full.
CLI::Validator finite_positive();
// The same for a finite number >= 0 ("--stop-change: must be finite and >= 0, got -1").
CLI::Validator finite_non_negative();

// --pcd-data ascii|binary|binary_compressed for the commands that write: the DATA encoding of a
// .pcd OUT (default: the input's, binary for a non-PCD input; ascii with --ascii). Binds `value`.
void add_pcd_data_option(CLI::App& app, std::string& value);

// `pnf filter --auto`'s report on stderr: the estimate, the rule's line where it was
// cross-validated ("rule would take"), and the choice; `seconds` the time it took.
void print_auto(const AutoChoice& choice, double seconds);

// `pnf filter`'s summary line for the rows it did not filter: points without normals (NaN) and
// invalid points (a NaN coordinate), kept in place by a PLY or PCD OUT and left out of a text
// one, which cannot hold NaN (README, "Formats"). Prints nothing when both are 0.
void print_rows_not_filtered(std::size_t without_normals, std::size_t invalid, const std::string& out);

// The WriteOptions for --ascii and --pcd-data (empty: not given).
WriteOptions write_options(bool ascii, const std::string& pcd_data);

}  // namespace pnf::cli
