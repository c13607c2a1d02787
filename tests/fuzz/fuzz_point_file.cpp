// libFuzzer target for the point file readers: the input bytes become a file with extension
// PNF_FUZZ_EXTENSION (".ply" or ".xyz"). Whatever the bytes, reading must either succeed or
// throw pnf::Error; a file that reads must write back (binary and ascii) and read again to the
// same positions and normals. Anything else (a crash, a sanitizer report, another exception, a
// changed value) is a bug.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pnf/error.hpp"
#include "pnf/point_file.hpp"

namespace {

std::string scratch_dir() {
  // Memory-backed when available: the fuzzer writes a file per input.
  return access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
}

const std::string& base_path() {
  static const std::string base = scratch_dir() + "/pnf_fuzz_" + std::to_string(getpid());
  return base;
}

bool same_cloud(const pnf::PointCloud& a, const pnf::PointCloud& b) {
  auto same = [](const std::vector<pnf::Vec3>& x, const std::vector<pnf::Vec3>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (x[i][k] != y[i][k]) return false;  // bit-exact: the readers promise it
    return true;
  };
  return same(a.positions, b.positions) && same(a.normals, b.normals);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string in = base_path() + PNF_FUZZ_EXTENSION;
  if (FILE* f = std::fopen(in.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    std::abort();
  }
  try {
    pnf::PointFile file = pnf::read_point_file(in);
    const pnf::PointCloud cloud = file.cloud();
    for (bool ascii : {false, true}) {
      const std::string out = base_path() + (ascii ? "_a.ply" : "_b.ply");
      pnf::write_point_file(out, file, pnf::WriteOptions{ascii});
      if (!same_cloud(cloud, pnf::read_point_file(out).cloud())) {
        std::fprintf(stderr, "round trip through %s changed the data\n", out.c_str());
        std::abort();
      }
    }
  } catch (const pnf::Error&) {
    // A clear error is the right answer to a bad file.
  }
  return 0;
}
