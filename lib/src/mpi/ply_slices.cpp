#include "ply_slices.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "agreement.hpp"
#include "ply_scalar.hpp"
#include "ply_writer.hpp"
#include "point_file_impl.hpp"

namespace pnf::mpi::detail {
namespace {

// Headers longer than this are not sliced (the rank-0 path reads them).
constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;
// Bytes copied at a time between files.
constexpr std::size_t kCopyChunk = std::size_t(8) << 20;

[[noreturn]] void io_error(const std::string& path, const std::string& what, int error_number) {
  throw Error(ErrorCode::io, path + ": " + what + ": " + std::strerror(error_number));
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream in(line);
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

class Descriptor {
 public:
  Descriptor(const std::string& path, int flags) : path_(path), fd_(::open(path.c_str(), flags, 0644)) {
    if (fd_ < 0) io_error(path, "cannot open", errno);
  }
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  void read_at(void* data, std::size_t size, std::uint64_t offset) const {
    auto* p = static_cast<unsigned char*>(data);
    while (size > 0) {
      const ssize_t got = ::pread(fd_, p, size, off_t(offset));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) io_error(path_, "cannot read at byte " + std::to_string(offset), errno);
      if (got == 0) {
        throw Error(ErrorCode::io,
                    path_ + ": the file ends at byte " + std::to_string(offset) + ", before its rows do");
      }
      p += got, size -= std::size_t(got), offset += std::uint64_t(got);
    }
  }
  void write_at(const void* data, std::size_t size, std::uint64_t offset) const {
    const auto* p = static_cast<const unsigned char*>(data);
    while (size > 0) {
      const ssize_t put = ::pwrite(fd_, p, size, off_t(offset));
      if (put < 0 && errno == EINTR) continue;
      if (put < 0) io_error(path_, "cannot write at byte " + std::to_string(offset), errno);
      p += put, size -= std::size_t(put), offset += std::uint64_t(put);
    }
  }
  void sync() const {
    if (::fsync(fd_) != 0) io_error(path_, "cannot sync", errno);
  }

 private:
  std::string path_;
  int fd_;
};

// The reader's own check of the vertices (check_vertices), on this slice's rows, with the vertex
// numbered in the whole file as one process names it.
void check_rows(const std::string& path, const PlySliceLayout& layout, const PlySlice& slice) {
  PointFile::Impl impl;
  impl.header = layout.header;
  locate_vertex_fields(impl, path);
  impl.header.elements[impl.vertex_element].count = slice.rows.size() / std::size_t(layout.row_size);
  impl.values.resize(impl.header.elements.size());
  impl.values[impl.vertex_element] = slice.rows;
  try {
    check_vertices(impl, path, {}, InvalidRows::nan_point);
  } catch (const Error& e) {
    const std::string message = e.what(), prefix = path + ": vertex ";
    if (message.rfind(prefix, 0) != 0) throw;
    std::size_t digits = 0;
    const unsigned long long local = std::stoull(message.substr(prefix.size()), &digits);
    throw Error(e.code(), prefix + std::to_string(slice.first + local) + message.substr(prefix.size() + digits));
  }
  if (impl.has_invalid_rows) {
    // The ranks split and exchange rows as points; invalid ones would need their own bookkeeping.
    std::size_t row = 0;
    while (row < impl.valid_rows.size() && impl.valid_rows[row] == row) ++row;
    const std::string what = impl.rows_without_normals > 0 ? "an invalid point (NaN coordinates) or has no normal (NaN)"
                                                           : "an invalid point (NaN coordinates)";
    throw Error(ErrorCode::invalid_input, path + ": vertex " + std::to_string(slice.first + row) + " is " + what +
                                              ", which distributed runs do not take; filter this file on one process");
  }
}

}  // namespace

PlySliceLayout read_slice_layout(const std::string& path) {
  PlySliceLayout layout;
  auto refuse = [&](const std::string& why) {
    layout.sliceable = false;
    layout.why_not = why;
    return layout;
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) return refuse("cannot open it");  // the rank-0 path reports it as one process does
  std::string line;
  std::size_t declarations = 0, bytes = 0;
  bool have_format = false;
  for (int number = 1;; ++number) {
    if (!std::getline(in, line)) return refuse("no end_header line");
    bytes += line.size() + 1;
    if (bytes > kMaxHeaderBytes || line.find('\r') != std::string::npos) return refuse("an unusual header");
    const std::vector<std::string> tokens = split(line);
    if (number == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply") return refuse("not a PLY file");
      continue;
    }
    if (tokens.empty()) continue;
    const std::string& keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") {
      std::size_t start = line.find(keyword) + keyword.size();
      if (start < line.size()) ++start;
      layout.header.comments.push_back(
          {keyword, start < line.size() ? line.substr(start) : std::string(), declarations});
    } else if (keyword == "format") {
      if (tokens.size() != 3 || tokens[1] != "binary_little_endian" || have_format) {
        return refuse("not binary_little_endian");
      }
      layout.header.encoding = PlyEncoding::binary_little_endian;
      layout.header.version = tokens[2];
      have_format = true;
      ++declarations;
    } else if (keyword == "element") {
      if (tokens.size() != 3 || !have_format) return refuse("a malformed element line");
      PlyElement element;
      element.name = tokens[1];
      char* end = nullptr;
      element.count = std::size_t(std::strtoull(tokens[2].c_str(), &end, 10));
      if (*end != '\0' || tokens[2][0] == '-') return refuse("a malformed element count");
      layout.header.elements.push_back(element);
      ++declarations;
    } else if (keyword == "property") {
      if (layout.header.elements.empty() || tokens.size() != 3) return refuse("a list or malformed property");
      PlyProperty property;
      if (!parse_scalar_name(tokens[1], property.type)) return refuse("an unknown property type");
      property.type_name = tokens[1];
      property.name = tokens[2];
      layout.header.elements.back().properties.push_back(property);
      ++declarations;
    } else if (keyword == "end_header") {
      if (tokens.size() != 1 || !have_format) return refuse("a malformed end_header line");
      break;
    } else {
      return refuse("an unknown header keyword");
    }
  }
  layout.body_offset = bytes;
  PointFile::Impl impl;
  impl.header = layout.header;
  try {
    locate_vertex_fields(impl, path);
  } catch (const Error&) {
    return refuse("no usable vertex element");  // the rank-0 path says what is wrong
  }
  if (!impl.fields.has_normals()) return refuse("no normals");
  std::uint64_t offset = layout.body_offset;
  for (std::size_t e = 0; e < layout.header.elements.size(); ++e) {
    const PlyElement& element = layout.header.elements[e];
    std::uint64_t row = 0;
    std::vector<std::size_t> at;
    for (const PlyProperty& p : element.properties) {
      at.push_back(std::size_t(row));
      row += scalar_size(p.type);
    }
    if (e == impl.vertex_element) {
      layout.vertex_offset = offset;
      layout.vertex_count = element.count;
      layout.row_size = row;
      const std::size_t pos[3] = {impl.fields.x, impl.fields.y, impl.fields.z};
      const std::size_t nor[3] = {impl.fields.nx, impl.fields.ny, impl.fields.nz};
      for (int k = 0; k < 3; ++k) {
        layout.position_offset[k] = at[pos[k]];
        layout.position_type[k] = element.properties[pos[k]].type;
        layout.normal_offset[k] = at[nor[k]];
        layout.normal_type[k] = element.properties[nor[k]].type;
        if (is_integer(layout.normal_type[k])) return refuse("integer normals");
      }
      layout.has_normals = true;
      if (impl.fields.radius != VertexFields::kNone) {
        layout.has_radius = true;
        layout.radius_offset = at[impl.fields.radius];
        layout.radius_type = element.properties[impl.fields.radius].type;
      }
    }
    offset += row * element.count;
  }
  layout.body_end = offset;
  // Bytes after the last element: one process refuses data there and accepts filler; the rank-0
  // path decides as it does. A file too short fails on the rank whose rows are missing.
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > layout.body_end) return refuse("bytes after the last element");
  layout.output_header = header_text(layout.header, false);
  layout.sliceable = true;
  return layout;
}

void slice_rows(const PlySliceLayout& layout, int rank, int ranks, std::uint64_t& first, std::uint64_t& count) {
  const auto bound = [&](int r) {
    return std::uint64_t((unsigned __int128)layout.vertex_count * std::uint64_t(r) / std::uint64_t(ranks));
  };
  first = bound(rank);
  count = bound(rank + 1) - first;
}

PlySlice read_slice(const std::string& path, const PlySliceLayout& layout, int rank, int ranks) {
  PlySlice slice;
  std::uint64_t count = 0;
  slice_rows(layout, rank, ranks, slice.first, count);
  slice.rows.resize(std::size_t(count * layout.row_size));
  const Descriptor in(path, O_RDONLY);
  in.read_at(slice.rows.data(), slice.rows.size(), layout.vertex_offset + slice.first * layout.row_size);
  check_rows(path, layout, slice);
  PointCloud& cloud = slice.cloud;
  cloud.positions.resize(std::size_t(count));
  cloud.normals.resize(std::size_t(count));
  if (layout.has_radius) cloud.radii.resize(std::size_t(count));
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned char* row = &slice.rows[i * layout.row_size];
    for (int k = 0; k < 3; ++k) {
      cloud.positions[i][std::size_t(k)] = load_as_double(layout.position_type[k], row + layout.position_offset[k]);
      cloud.normals[i][std::size_t(k)] = load_as_double(layout.normal_type[k], row + layout.normal_offset[k]);
    }
    if (layout.has_radius) cloud.radii[i] = load_as_double(layout.radius_type, row + layout.radius_offset);
  }
  return slice;
}

void write_slices(MPI_Comm comm, const std::string& in_path, const std::string& path, const PlySliceLayout& layout,
                  PlySlice& slice, const std::vector<Vec3>& normals) {
  const Agreement agree(comm);
  // Rank 0 creates the file (0666 less the umask, as write_point_file's); then every rank opens it.
  agree.run([&] {
    if (agree.rank() != 0) return;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) io_error(path, "cannot create", errno);
    ::close(fd);
  });
  agree.run([&] {
    for (std::size_t i = 0; i < normals.size(); ++i) {
      unsigned char* row = &slice.rows[i * layout.row_size];
      for (int k = 0; k < 3; ++k)
        store_real(layout.normal_type[k], normals[i][std::size_t(k)], row + layout.normal_offset[k]);
    }
    const Descriptor out(path, O_WRONLY);
    // The output is the input with the header rewritten as write_point_file writes it.
    const std::uint64_t shift = layout.output_header.size();
    const auto out_offset = [&](std::uint64_t in_offset) { return in_offset - layout.body_offset + shift; };
    out.write_at(slice.rows.data(), slice.rows.size(),
                 out_offset(layout.vertex_offset + slice.first * layout.row_size));
    if (agree.rank() == 0) {
      out.write_at(layout.output_header.data(), layout.output_header.size(), 0);
      // The other elements' bytes, before and after the vertex rows, copied unchanged.
      const Descriptor in(in_path, O_RDONLY);
      const std::uint64_t vertex_end = layout.vertex_offset + layout.vertex_count * layout.row_size;
      std::vector<unsigned char> buffer;
      for (auto [from, to] :
           {std::pair{layout.body_offset, layout.vertex_offset}, std::pair{vertex_end, layout.body_end}}) {
        for (std::uint64_t at = from; at < to; at += kCopyChunk) {
          buffer.resize(std::size_t(std::min<std::uint64_t>(kCopyChunk, to - at)));
          in.read_at(buffer.data(), buffer.size(), at);
          out.write_at(buffer.data(), buffer.size(), out_offset(at));
        }
      }
    }
    out.sync();
  });
}

}  // namespace pnf::mpi::detail
