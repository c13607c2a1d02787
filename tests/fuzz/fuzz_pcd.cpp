// libFuzzer target for the PCD reader: the input bytes become a .pcd file. Whatever the bytes,
// reading must either succeed or throw pnf::Error. A file that reads must write back as PCD in
// every DATA kind (ascii, binary, binary_compressed) and read again to the same rows, the same
// valid points and the same positions and normals, bit for bit; binary output must repeat the
// values of every row exactly. Anything else (a crash, a sanitizer report, another exception, an
// error reading pnf's own output, a changed value) is a bug.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "pnf/error.hpp"
#include "pnf/point_file.hpp"

namespace {

std::string scratch_dir() {
  // Memory-backed when available: the fuzzer writes files per input.
  return access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
}

const std::string& base_path() {
  static const std::string base = scratch_dir() + "/pnf_fuzz_pcd_" + std::to_string(getpid());
  return base;
}

bool same_bits(const std::vector<pnf::Vec3>& x, const std::vector<pnf::Vec3>& y) {
  return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(pnf::Vec3)) == 0);
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "%s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string in = base_path() + ".pcd";
  if (FILE* f = std::fopen(in.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    std::abort();
  }
  pnf::PointFile file;
  try {
    file = pnf::read_point_file(in);
  } catch (const pnf::Error&) {
    return 0;  // a clear error is the right answer to a bad file
  }
  const pnf::PointCloud cloud = file.cloud();
  for (const pnf::PcdData kind : {pnf::PcdData::ascii, pnf::PcdData::binary, pnf::PcdData::binary_compressed}) {
    const std::string out = base_path() + "_out_" + pnf::to_string(kind) + ".pcd";
    pnf::WriteOptions options;
    options.pcd_data = kind;
    try {
      pnf::write_point_file(out, file, options);
      const pnf::PointFile back = pnf::read_point_file(out);
      const pnf::PointCloud again = back.cloud();
      if (back.size() != file.size() || back.valid_count() != file.valid_count() ||
          !same_bits(cloud.positions, again.positions) || !same_bits(cloud.normals, again.normals)) {
        fail("round trip through DATA " + std::string(pnf::to_string(kind)) + " changed the data");
      }
      if (kind == pnf::PcdData::binary && back.element_values(0) != file.element_values(0)) {
        fail("round trip through DATA binary changed a value's bytes");
      }
    } catch (const pnf::Error& e) {
      fail(std::string("writing or rereading pnf's own PCD output failed: ") + e.what());
    }
  }
  return 0;
}
