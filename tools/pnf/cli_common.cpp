#include "cli_common.hpp"

#include <unistd.h>

#include <cstdio>
#include <exception>

namespace pnf::cli {

int report(const Error& e, Stage stage) {
  std::fprintf(stderr, "pnf: error: %s\n", e.what());
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
  if (quiet || !isatty(STDERR_FILENO)) return [](const PassProgress&) { return true; };
  return [](const PassProgress& p) {
    constexpr int kWidth = 30;
    int filled = p.passes > 0 ? kWidth * p.pass / p.passes : kWidth;
    std::fprintf(stderr, "\r  pass %d/%d [%s%s] %.2f s", p.pass, p.passes, std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), p.seconds);
    if (p.pass == p.passes) std::fprintf(stderr, "\r%*s\r", kWidth + 40, "");
    std::fflush(stderr);
    return true;
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

void DeviceFlags::add_to(CLI::App& app, bool with_backend) {
  app.add_option("--device", device,
                 "OpenCL device: cpu, gpu, accelerator, P:D, or part of a name (default: $PNF_DEVICE, "
                 "else the first GPU, else the first CPU)");
  if (with_backend) {
    app.add_option("--backend", backend, "opencl (default) or reference (double precision, CPU, no OpenCL)")
        ->check(CLI::IsMember({"opencl", "reference"}));
  }
}

FilterOptions DeviceFlags::options() const {
  FilterOptions o;
  o.backend = backend == "reference" ? Backend::reference : Backend::opencl;
  o.device = device;
  return o;
}

}  // namespace pnf::cli
