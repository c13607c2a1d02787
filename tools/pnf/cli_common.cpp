#include "cli_common.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>

#include "pnf/options_text.hpp"
#include "progress_text.hpp"

namespace pnf::cli {
namespace {

// Set by the SIGINT / SIGTERM handler, read by the progress callback after each pass and about
// every 0.2 s while lists are built or normals estimated.
volatile std::sig_atomic_t interrupted = 0;

void on_interrupt(int) { interrupted = 1; }

// Where stderr is not a terminal (a batch log; rank 0 under mpirun), a progress line at most this
// often, the first only after as long: a run shorter than this prints none.
constexpr double kProgressLineSeconds = 10;

// The first SIGINT or SIGTERM asks the run to stop at its next progress report; SA_RESETHAND puts the
// default action back, so a second one ends the process at once.
void stop_on_interrupt() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

int report(const Error& e, Stage stage) {
  std::fprintf(stderr, "pnf: error: %s\n", e.what());
  return exit_code(e, stage);
}

int exit_code(const Error& e, Stage stage) {
  switch (e.code()) {
    case ErrorCode::invalid_argument: return kUsage;
    case ErrorCode::invalid_input: return kInput;
    case ErrorCode::device: return kDevice;
    case ErrorCode::cancelled: return kCancelled;
    case ErrorCode::io: return stage == Stage::writing ? kOutput : kInput;
  }
  return kInternal;
}

ProgressCallback progress_bar(bool quiet) {
  stop_on_interrupt();
  if (quiet) return [](const PassProgress&) { return interrupted == 0; };
  if (!isatty(STDERR_FILENO)) {
    auto lines = std::make_shared<ProgressLines>(stderr, kProgressLineSeconds);
    return [lines](const PassProgress& p) {
      (*lines)(p);
      return interrupted == 0;
    };
  }
  return [](const PassProgress& p) {
    constexpr int kWidth = 30;
    const ProgressText text = progress_text(p);
    const int filled = int(kWidth * text.done);
    std::fprintf(stderr, "\r  %-14s [%s%s] %.2f s ", text.label.c_str(), std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), p.seconds);
    const bool last =
        p.stage == ProgressStage::pass ? p.pass == p.passes : p.stage == ProgressStage::estimate && text.done >= 1;
    if (last || interrupted) {
      std::fprintf(stderr, "\r%*s\r", kWidth + 40, "");
    }
    std::fflush(stderr);
    return interrupted == 0;
  };
}

int guarded(Stage& stage, const std::function<int()>& body) {
  try {
    return body();
  } catch (const Error& e) {
    return report(e, stage);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "pnf: error: out of memory\n");
    return kInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pnf: internal error: %s\n", e.what());
    return kInternal;
  }
}

namespace {

// A validator of a finite number > 0, or >= 0 with `zero_too`.
CLI::Validator finite_above_zero(bool zero_too, const std::string& name) {
  const std::string bound = zero_too ? ">= 0" : "> 0";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || value < 0 || (!zero_too && value == 0)) {
          return "must be finite and " + bound + ", got " + text;
        }
        return "";
      },
      name, name);
}

}  // namespace

CLI::Validator finite_positive() { return finite_above_zero(false, "POSITIVE"); }
CLI::Validator finite_non_negative() { return finite_above_zero(true, "NON_NEGATIVE"); }

void add_pcd_data_option(CLI::App& app, std::string& value) {
  app.add_option("--pcd-data", value,
                 "DATA of a .pcd OUT: ascii, binary or binary_compressed (default: the input's; binary for a "
                 "non-PCD input; ascii with --ascii)")
      ->check(CLI::IsMember({"ascii", "binary", "binary_compressed"}));
}

WriteOptions write_options(bool ascii, const std::string& pcd_data) {
  WriteOptions options;
  options.ascii = ascii;
  for (const PcdData data : {PcdData::ascii, PcdData::binary, PcdData::binary_compressed}) {
    if (pcd_data == to_string(data)) options.pcd_data = data;
  }
  return options;
}

void DeviceFlags::add_to(CLI::App& app, bool with_backend) {
  app.add_option("--device", device,
                 "where to run: reference (CPU, double), opencl, opencl:SELECTOR or SELECTOR, where SELECTOR is "
                 "cpu, gpu, accelerator, P:D or part of a name (default: $PNF_DEVICE, else the first GPU, else "
                 "the first CPU)");
  if (with_backend) {
    app.add_option("--backend", backend,
                   "opencl (default) or reference (double precision, CPU, no OpenCL; same as --device reference, "
                   "and refused beside an OpenCL --device)")
        ->check(CLI::IsMember({"opencl", "reference"}));
  }
  // The pair is checked as soon as the command line is read (a usage error, exit 2), through the
  // library's parser, which Python's backend= and device= go through too.
  app.parse_complete_callback([this, with_backend] {
    try {
      (void)options();
    } catch (const Error& e) {
      throw CLI::ValidationError(with_backend ? "--backend/--device" : "--device", e.what());
    }
  });
}

FilterOptions DeviceFlags::options() const {
  FilterOptions o;
  o.device = parse_backend_and_device(backend, device);
  return o;
}

void print_rows_not_filtered(std::size_t without_normals, std::size_t invalid, const std::string& out) {
  if (without_normals == 0 && invalid == 0) return;
  const PointFileFormat format = point_file_format(out);
  const bool text = format != PointFileFormat::ply && format != PointFileFormat::pcd;
  auto line = [&](std::size_t count, const char* what) {
    if (count == 0) return;
    if (text) {
      std::fprintf(stderr, "  left out     %zu %s (a text file cannot hold NaN)\n", count, what);
    } else {
      std::fprintf(stderr, "  kept         %zu %s as they were\n", count, what);
    }
  };
  line(without_normals, "points without normals (NaN)");
  line(invalid, "invalid points (a NaN coordinate)");
}

void print_auto(const AutoChoice& choice, double seconds) {
  const DataEstimate& e = choice.estimate;
  std::fprintf(stderr,
               "pnf filter --auto: estimated from %zu of %zu points (fits of %d neighbours, radius %.4g), chose and "
               "filtered in %.2f s\n",
               e.samples, e.points, e.fit_neighbours, e.fit_radius, seconds);
  std::fprintf(stderr, "  mean radius      %.6g model units (%s); area spacing %.6g\n", e.mean_radius,
               to_string(e.radius_source), e.area_spacing);
  std::fprintf(stderr, "  position noise   %.4g model units = %.3g area spacings (along the normal)\n",
               e.position_noise, e.position_noise_area_spacings());
  if (e.normal_noise_deg >= 0) {
    std::fprintf(stderr,
                 "  normal noise     %.3g deg RMS (%.3g from the neighbours' normals, %.3g from the chords), errors of "
                 "nearby normals correlated %.2f, coupled to the positions %.2f; crease length in the normals %.2f "
                 "per size\n",
                 e.normal_noise_deg, e.normal_noise_neighbours_deg, e.normal_noise_chords_deg,
                 e.normal_error_correlation, e.normal_position_coupling, e.normal_crease_length);
  }
  std::fprintf(stderr,
               "  shape            crease length %.2f per size (%.0f%% of the samples at an edge), sharpness %.3f, "
               "%.0f%% of the smooth ones curved\n",
               e.crease_length, 100 * e.feature_share, e.crease_sharpness, 100 * e.curved_share);
  std::fprintf(stderr, "  chose            %s\n", choice.rule.c_str());
  if (!choice.judged.empty()) std::fprintf(stderr, "  passes           %s\n", choice.judged.c_str());
}

}  // namespace pnf::cli
