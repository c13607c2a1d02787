#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string_view>

#include "atomic_file.hpp"
#include "pcd_header.hpp"
#include "pcd_reader.hpp"
#include "pcd_writer.hpp"
#include "ply_reader.hpp"
#include "ply_scalar.hpp"
#include "ply_writer.hpp"
#include "pnf/error.hpp"
#include "point_file_impl.hpp"
#include "row_layout.hpp"
#include "text_points.hpp"

namespace pnf {
namespace {

PlyProperty real_property(const char* name, PlyScalar type) {
  PlyProperty property;
  property.name = name;
  property.type = type;
  property.type_name = scalar_name(type);
  return property;
}

// Appends nx ny nz of impl.added_normal_type to the vertex element, with zero values; for a
// PCD file, float fields normal_x normal_y normal_z.
void add_normal_properties(PointFile::Impl& impl) {
  const bool pcd = impl.source_format == PointFileFormat::pcd;
  PlyHeader& header = impl.header;
  PlyElement& vertex = header.elements[impl.vertex_element];
  const std::size_t old_properties = vertex.properties.size();
  // Header lines before the new properties: format, then each element line and its properties
  // up to the vertex element. Comments after that point move down with the lines below them.
  std::size_t insert_at = 1;
  for (std::size_t e = 0; e <= impl.vertex_element; ++e) {
    insert_at += 1 + header.elements[e].properties.size();
  }
  for (PlyComment& comment : header.comments) {
    if (comment.position > insert_at) comment.position += 3;
  }
  const PlyScalar type = impl.added_normal_type;
  const char* const names[2][3] = {{"nx", "ny", "nz"}, {"normal_x", "normal_y", "normal_z"}};
  for (const char* name : names[pcd ? 1 : 0]) {
    vertex.properties.push_back(real_property(name, type));
    if (!pcd) continue;
    PcdField field;
    field.name = name;
    pcd_type_of(type, field.type, field.size);
    impl.pcd.fields.push_back(std::move(field));
  }
  impl.fields.nx = old_properties;
  impl.fields.ny = old_properties + 1;
  impl.fields.nz = old_properties + 2;

  const std::size_t added = 3 * scalar_size(type);
  std::vector<unsigned char>& old_values = impl.values[impl.vertex_element];
  std::vector<unsigned char> values;
  values.reserve(old_values.size() + vertex.count * added);
  // Lay out rows with the old property list: the new properties are not in them yet.
  const std::vector<PlyProperty> old_list(vertex.properties.begin(), vertex.properties.begin() + old_properties);
  RowLayout layout(old_list);
  const unsigned char* row = old_values.data();
  for (std::size_t r = 0; r < vertex.count; ++r) {
    const std::size_t row_size = layout.measure(row);
    values.insert(values.end(), row, row + row_size);
    values.insert(values.end(), added, 0);
    row += row_size;
  }
  old_values.swap(values);

  if (!impl.ascii_rows.empty()) {
    // Placeholders, replaced by rewrite_vertex_tokens.
    std::string& text = impl.ascii_rows[impl.vertex_element];
    std::string with_normals;
    with_normals.reserve(text.size() + vertex.count * 6);
    for (const char c : text) {
      if (c == '\n') with_normals += " 0 0 0";
      with_normals += c;
    }
    text.swap(with_normals);
  }
}

// Replaces the tokens of the vertex properties `rewritten_properties` (indices) in the stored
// ascii vertex rows with their stored values; every other token stays as read.
void rewrite_vertex_tokens(PointFile::Impl& impl, const std::vector<std::size_t>& rewritten_properties) {
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  const std::vector<PlyProperty>& properties = vertex.properties;
  const std::string& text = impl.ascii_rows[impl.vertex_element];
  std::vector<bool> replaced(properties.size(), false);
  for (const std::size_t p : rewritten_properties) replaced[p] = true;
  std::string rewritten;
  rewritten.reserve(text.size());
  RowLayout layout(properties);
  const unsigned char* row = impl.values[impl.vertex_element].data();
  std::size_t at = 0;  // start of the current token in `text`
  const auto next_token = [&]() {
    const std::size_t end = text.find_first_of(" \n", at);
    const std::string_view token(text.data() + at, end - at);
    at = end + 1;
    return token;
  };
  for (std::size_t r = 0; r < vertex.count; ++r) {
    const std::size_t row_size = layout.measure(row);
    for (std::size_t p = 0; p < properties.size(); ++p) {
      if (p > 0) rewritten += ' ';
      const std::string_view token = next_token();
      if (replaced[p]) {
        append_token(properties[p].type, row + layout.offset(p), rewritten);
        continue;
      }
      rewritten += token;
      if (!properties[p].is_list) continue;
      std::uint64_t count = 0;
      load_count(properties[p].count_type, row + layout.offset(p), count);
      for (std::uint64_t i = 0; i < count; ++i) {
        rewritten += ' ';
        rewritten += next_token();
      }
    }
    rewritten += '\n';
    row += row_size;
  }
  impl.ascii_rows[impl.vertex_element].swap(rewritten);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_normal(const Vec3& normal, std::size_t index, const char* where) {
  const bool finite = std::isfinite(normal[0]) && std::isfinite(normal[1]) && std::isfinite(normal[2]);
  if (!finite || (normal[0] == 0 && normal[1] == 0 && normal[2] == 0)) {
    throw Error(ErrorCode::invalid_argument, std::string(where) + ": normal " + std::to_string(index) +
                                                 (finite ? " is zero-length" : " is not finite"));
  }
}

// Visits every vertex row in file order with the index of its point among cloud()'s `points`
// (the rows left out of cloud(), invalid or without normals, get npos): store(row, layout, i).
constexpr std::size_t kNoPoint = std::size_t(-1);
template <typename Store>
void for_each_vertex_row(PointFile::Impl& impl, std::size_t points, Store&& store) {
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  RowLayout layout(vertex.properties);
  unsigned char* row = impl.values[impl.vertex_element].data();
  std::size_t i = 0;  // the next valid point
  for (std::size_t r = 0; r < vertex.count; ++r) {
    const std::size_t row_size = layout.measure(row);
    const bool valid = !impl.has_invalid_rows || (i < points && impl.valid_rows[i] == r);
    store(row, layout, valid ? i++ : kNoPoint);
    row += row_size;
  }
}

}  // namespace

PointFileFormat point_file_format(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".ply") return PointFileFormat::ply;
  if (extension == ".xyz") return PointFileFormat::xyz;
  if (extension == ".xyzn") return PointFileFormat::xyzn;
  if (extension == ".pwn") return PointFileFormat::pwn;
  if (extension == ".pcd") return PointFileFormat::pcd;
  throw Error(ErrorCode::invalid_argument,
              path + ": unknown point file extension '" + extension + "' (expected .ply, .pcd, .xyz, .xyzn or .pwn)");
}

void check_write_options(const std::string& path, const WriteOptions& options) {
  if (options.pcd_data && point_file_format(path) != PointFileFormat::pcd) {
    throw Error(ErrorCode::invalid_argument, path + ": a PCD DATA encoding (--pcd-data " +
                                                 to_string(*options.pcd_data) +
                                                 ") was asked for a file that is not .pcd");
  }
}

PointFile::PointFile() : PointFile(PointCloud{}) {}

PointFile::PointFile(const PointCloud& cloud) : impl_(std::make_unique<Impl>()) {
  constexpr const char* kWhere = "PointFile(PointCloud)";
  const std::size_t n = cloud.size();
  if (cloud.has_normals() && cloud.normals.size() != n) {
    throw Error(ErrorCode::invalid_argument, std::string(kWhere) + ": " + std::to_string(cloud.normals.size()) +
                                                 " normals for " + std::to_string(n) + " points");
  }
  if (cloud.has_radii() && cloud.radii.size() != n) {
    throw Error(ErrorCode::invalid_argument, std::string(kWhere) + ": " + std::to_string(cloud.radii.size()) +
                                                 " radii for " + std::to_string(n) + " points");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = cloud.positions[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error(ErrorCode::invalid_argument,
                  std::string(kWhere) + ": position " + std::to_string(i) + " is not finite");
    }
    if (cloud.has_normals()) check_normal(cloud.normals[i], i, kWhere);
    if (cloud.has_radii() && !std::isfinite(cloud.radii[i])) {
      throw Error(ErrorCode::invalid_argument,
                  std::string(kWhere) + ": radius " + std::to_string(i) + " is not finite");
    }
  }
  Impl& impl = *impl_;
  impl.added_normal_type = PlyScalar::float64;
  PlyElement vertex;
  vertex.name = "vertex";
  vertex.count = n;
  for (const char* name : {"x", "y", "z"}) {
    vertex.properties.push_back(real_property(name, PlyScalar::float64));
  }
  if (cloud.has_normals()) {
    for (const char* name : {"nx", "ny", "nz"}) {
      vertex.properties.push_back(real_property(name, PlyScalar::float64));
    }
  }
  if (cloud.has_radii()) vertex.properties.push_back(real_property("radius", PlyScalar::float64));
  const std::size_t row_size = vertex.properties.size() * sizeof(double);
  impl.header.elements.push_back(std::move(vertex));
  std::vector<unsigned char>& values = impl.values.emplace_back(n * row_size);
  unsigned char* at = values.data();
  const auto put = [&at](double value) {
    store_real(PlyScalar::float64, value, at);
    at += sizeof(double);
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (const double value : cloud.positions[i]) put(value);
    if (cloud.has_normals()) {
      for (const double value : cloud.normals[i]) put(value);
    }
    if (cloud.has_radii()) put(cloud.radii[i]);
  }
  locate_vertex_fields(impl, kWhere);
}

PointFile::PointFile(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
PointFile::PointFile(const PointFile& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
PointFile::PointFile(PointFile&& other) noexcept = default;
PointFile& PointFile::operator=(const PointFile& other) {
  if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
  return *this;
}
PointFile& PointFile::operator=(PointFile&& other) noexcept = default;
PointFile::~PointFile() = default;

PointFileFormat PointFile::source_format() const { return impl_->source_format; }

const PlyHeader& PointFile::header() const { return impl_->header; }

std::size_t PointFile::size() const { return impl_->header.elements[impl_->vertex_element].count; }

const PcdHeader* PointFile::pcd_header() const {
  return impl_->source_format == PointFileFormat::pcd ? &impl_->pcd : nullptr;
}

std::size_t PointFile::valid_count() const { return impl_->has_invalid_rows ? impl_->valid_rows.size() : size(); }

std::size_t PointFile::without_normals() const { return impl_->rows_without_normals; }

std::size_t PointFile::row_of_point(std::size_t i) const {
  if (i >= valid_count()) {
    throw Error(ErrorCode::invalid_argument,
                "row_of_point: point " + std::to_string(i) + " of " + std::to_string(valid_count()) + " valid points");
  }
  return impl_->has_invalid_rows ? impl_->valid_rows[i] : i;
}

bool PointFile::has_normals() const { return impl_->fields.has_normals(); }

PointCloud PointFile::cloud() const {
  const Impl& impl = *impl_;
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  const std::vector<PlyProperty>& properties = vertex.properties;
  const VertexFields& fields = impl.fields;
  const std::size_t points = valid_count();
  PointCloud cloud;
  cloud.positions.resize(points);
  if (fields.has_normals()) cloud.normals.resize(points);
  if (fields.radius != VertexFields::kNone) cloud.radii.resize(points);
  RowLayout layout(properties);
  const unsigned char* row = impl.values[impl.vertex_element].data();
  const auto load = [&](std::size_t property) {
    return load_as_double(properties[property].type, row + layout.offset(property));
  };
  std::size_t i = 0;  // the next valid point
  for (std::size_t r = 0; r < vertex.count && i < points; ++r) {
    const std::size_t row_size = layout.measure(row);
    if (!impl.has_invalid_rows || impl.valid_rows[i] == r) {
      cloud.positions[i] = {load(fields.x), load(fields.y), load(fields.z)};
      if (fields.has_normals()) cloud.normals[i] = {load(fields.nx), load(fields.ny), load(fields.nz)};
      if (fields.radius != VertexFields::kNone) cloud.radii[i] = load(fields.radius);
      ++i;
    }
    row += row_size;
  }
  return cloud;
}

const PlyProperty* PointFile::integer_normal_property() const {
  const Impl& impl = *impl_;
  if (!impl.fields.has_normals()) return nullptr;
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  for (const std::size_t field : {impl.fields.nx, impl.fields.ny, impl.fields.nz}) {
    if (is_integer(vertex.properties[field].type)) return &vertex.properties[field];
  }
  return nullptr;
}

void PointFile::set_normals(const std::vector<Vec3>& normals) {
  constexpr const char* kWhere = "set_normals";
  Impl& impl = *impl_;
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  const std::size_t points = valid_count();
  if (normals.size() != points) {
    throw Error(ErrorCode::invalid_argument, std::string(kWhere) + ": " + std::to_string(normals.size()) +
                                                 " normals for " + std::to_string(points) +
                                                 (impl.has_invalid_rows ? " valid points" : " vertices"));
  }
  for (std::size_t i = 0; i < normals.size(); ++i) check_normal(normals[i], i, kWhere);
  if (impl.fields.has_normals()) {
    if (const PlyProperty* property = integer_normal_property()) {
      throw Error(ErrorCode::invalid_input, std::string(kWhere) + ": vertex property '" + property->name +
                                                "' is declared '" + property->type_name +
                                                "', an integer type that cannot hold normals");
    }
  } else {
    add_normal_properties(impl);
  }
  const std::vector<PlyProperty>& properties = vertex.properties;
  const std::size_t fields[3] = {impl.fields.nx, impl.fields.ny, impl.fields.nz};
  for_each_vertex_row(impl, points, [&](unsigned char* row, const RowLayout& layout, std::size_t i) {
    // An invalid point (a row with a NaN coordinate) or a point without a normal: NaN, as PCL
    // gives it.
    const Vec3 normal = i != kNoPoint ? normals[i] : Vec3{kNaN, kNaN, kNaN};
    for (int axis = 0; axis < 3; ++axis) {
      store_real(properties[fields[axis]].type, normal[axis], row + layout.offset(fields[axis]));
    }
  });
  if (!impl.ascii_rows.empty()) rewrite_vertex_tokens(impl, {fields[0], fields[1], fields[2]});
}

bool PointFile::has_scalar_property(const std::string& name) const {
  for (const PlyProperty& property : impl_->header.elements[impl_->vertex_element].properties) {
    if (property.name == name && !property.is_list) return true;
  }
  return false;
}

void PointFile::set_scalar_property(const std::string& name, const std::vector<double>& values) {
  constexpr const char* kWhere = "set_scalar_property";
  Impl& impl = *impl_;
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  const std::vector<PlyProperty>& properties = vertex.properties;
  std::size_t field = properties.size();
  for (std::size_t p = 0; p < properties.size(); ++p) {
    if (properties[p].name == name && !properties[p].is_list) field = p;
  }
  if (field == properties.size()) {
    throw Error(ErrorCode::invalid_argument,
                std::string(kWhere) + ": the vertex element has no scalar property '" + name + "'");
  }
  const std::size_t xyz[3] = {impl.fields.x, impl.fields.y, impl.fields.z};
  const std::size_t normals[3] = {impl.fields.nx, impl.fields.ny, impl.fields.nz};
  if (std::find(std::begin(xyz), std::end(xyz), field) != std::end(xyz) ||
      std::find(std::begin(normals), std::end(normals), field) != std::end(normals)) {
    throw Error(ErrorCode::invalid_argument, std::string(kWhere) + ": '" + name +
                                                 "' is a coordinate or a normal component (set_normals sets normals)");
  }
  if (is_integer(properties[field].type)) {
    throw Error(ErrorCode::invalid_input, std::string(kWhere) + ": vertex property '" + name + "' is declared '" +
                                              properties[field].type_name + "', an integer type");
  }
  const std::size_t points = valid_count();
  if (values.size() != points) {
    throw Error(ErrorCode::invalid_argument, std::string(kWhere) + ": " + std::to_string(values.size()) +
                                                 " values for " + std::to_string(points) +
                                                 (impl.has_invalid_rows ? " valid points" : " vertices"));
  }
  for_each_vertex_row(impl, points, [&](unsigned char* row, const RowLayout& layout, std::size_t i) {
    // As set_normals: a row left out of cloud() has no fit, so NaN (as PCL gives it).
    store_real(properties[field].type, i != kNoPoint ? values[i] : kNaN, row + layout.offset(field));
  });
  if (!impl.ascii_rows.empty()) rewrite_vertex_tokens(impl, {field});
}

const std::vector<unsigned char>& PointFile::element_values(std::size_t element) const {
  if (element >= impl_->values.size()) {
    throw Error(ErrorCode::invalid_argument,
                "element_values: element " + std::to_string(element) + " of " + std::to_string(impl_->values.size()));
  }
  return impl_->values[element];
}

PointFile read_point_file(const std::string& path, const ReadOptions& options) {
  const PointFileFormat format = point_file_format(path);
  if (format == PointFileFormat::ply) return PointFile(read_ply(path, options));
  if (format == PointFileFormat::pcd) return PointFile(read_pcd(path, options));
  return PointFile(read_text_points(path, format, options));
}

void write_point_file(const std::string& path, const PointFile& file, const WriteOptions& options) {
  const PointFileFormat format = point_file_format(path);
  const bool needs_normals = format == PointFileFormat::xyzn || format == PointFileFormat::pwn;
  if (needs_normals && !file.has_normals()) {
    throw Error(ErrorCode::invalid_argument,
                path + ": this format stores x y z nx ny nz, and the points have no normals");
  }
  const PointFile::Impl& impl = *file.impl_;
  if (format == PointFileFormat::ply) {
    for (const PlyProperty& property : impl.header.elements[impl.vertex_element].properties) {
      if (property.type == PlyScalar::int64 || property.type == PlyScalar::uint64) {
        throw Error(ErrorCode::invalid_argument, path + ": vertex property '" + property.name + "' is " +
                                                     property.type_name + ", and PLY has no 64-bit integer type");
      }
    }
  }
  AtomicFile out(path);
  if (format == PointFileFormat::ply) {
    write_ply(impl, options.ascii, out);
  } else if (format == PointFileFormat::pcd) {
    const PcdData source_data = impl.source_format == PointFileFormat::pcd ? impl.pcd.data : PcdData::binary;
    write_pcd(impl, options.pcd_data.value_or(options.ascii ? PcdData::ascii : source_data), path, out);
  } else {
    write_text_points(file.cloud(), out);
  }
  out.commit();
}

const char* to_string(PlyEncoding encoding) {
  switch (encoding) {
    case PlyEncoding::ascii: return "ascii";
    case PlyEncoding::binary_little_endian: return "binary_little_endian";
    case PlyEncoding::binary_big_endian: return "binary_big_endian";
  }
  return "ascii";
}

}  // namespace pnf
