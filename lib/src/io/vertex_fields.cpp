// Finding and checking the vertex properties pnf uses (positions, normals, radius).
#include <cmath>
#include <string>

#include "ply_scalar.hpp"
#include "pnf/error.hpp"
#include "point_file_impl.hpp"
#include "row_layout.hpp"

namespace pnf {
namespace {

// The two spellings of normals: the common one and PCL's.
constexpr const char* kNormalNames[2][3] = {{"nx", "ny", "nz"}, {"normal_x", "normal_y", "normal_z"}};

std::size_t find_property(const PlyElement& element, const char* name) {
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    if (element.properties[p].name == name) return p;
  }
  return VertexFields::kNone;
}

std::string describe_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+infinity" : "-infinity";
  return std::to_string(value);
}

}  // namespace

void locate_vertex_fields(PointFile::Impl& impl, const std::string& path) {
  const auto fail = [&path](const std::string& what) { throw Error(ErrorCode::invalid_input, path + ": " + what); };
  const std::vector<PlyElement>& elements = impl.header.elements;
  std::size_t vertex = elements.size();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].name == "vertex") vertex = e;
  }
  if (vertex == elements.size()) fail("no 'vertex' element");
  impl.vertex_element = vertex;
  const PlyElement& element = elements[vertex];
  VertexFields fields;
  const auto require_scalar = [&](std::size_t index) {
    if (index != VertexFields::kNone && element.properties[index].is_list) {
      fail("vertex property '" + element.properties[index].name + "' is a list, not a scalar");
    }
  };
  std::size_t* positions[3] = {&fields.x, &fields.y, &fields.z};
  const char* position_names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    *positions[axis] = find_property(element, position_names[axis]);
    if (*positions[axis] == VertexFields::kNone) {
      fail(std::string("the vertex element has no '") + position_names[axis] + "' property");
    }
    require_scalar(*positions[axis]);
  }
  std::size_t* normals[3] = {&fields.nx, &fields.ny, &fields.nz};
  for (const auto& names : kNormalNames) {
    std::size_t found[3];
    int present = 0;
    for (int axis = 0; axis < 3; ++axis) {
      found[axis] = find_property(element, names[axis]);
      if (found[axis] != VertexFields::kNone) ++present;
    }
    if (present == 0) continue;
    if (present != 3) {
      fail(std::string("the vertex element has only some of '") + names[0] + "', '" + names[1] + "', '" + names[2] +
           "'");
    }
    if (fields.has_normals()) fail("the vertex element has normals under two names");
    for (int axis = 0; axis < 3; ++axis) {
      *normals[axis] = found[axis];
      require_scalar(found[axis]);
    }
  }
  fields.radius = find_property(element, "radius");
  require_scalar(fields.radius);
  impl.fields = fields;
}

void check_vertices(PointFile::Impl& impl, const std::string& path, const std::vector<std::size_t>& row_lines,
                    InvalidRows invalid_rows, bool check_normals) {
  const PlyElement& element = impl.header.elements[impl.vertex_element];
  const VertexFields& fields = impl.fields;
  const unsigned char* row = impl.values[impl.vertex_element].data();
  RowLayout layout(element.properties);
  const auto fail = [&](std::size_t vertex, const std::string& what) {
    std::string where = path + ": ";
    if (vertex < row_lines.size()) where += "line " + std::to_string(row_lines[vertex]) + ", ";
    throw Error(ErrorCode::invalid_input, where +
                                              (invalid_rows == InvalidRows::any_nan_coordinate ? "point " : "vertex ") +
                                              std::to_string(vertex) + ": " + what);
  };
  const auto load = [&](std::size_t property) {
    return load_as_double(element.properties[property].type, row + layout.offset(property));
  };
  const std::size_t position_fields[3] = {fields.x, fields.y, fields.z};
  const std::size_t normal_fields[3] = {fields.nx, fields.ny, fields.nz};
  std::vector<std::size_t> valid_rows;
  impl.has_invalid_rows = false;
  impl.rows_without_normals = 0;
  for (std::size_t vertex = 0; vertex < element.count; ++vertex) {
    const std::size_t row_size = layout.measure(row);
    if (invalid_rows != InvalidRows::none) {
      const bool x = std::isnan(load(fields.x)), y = std::isnan(load(fields.y)), z = std::isnan(load(fields.z));
      const bool nan_normal = fields.has_normals() && std::isnan(load(fields.nx)) && std::isnan(load(fields.ny)) &&
                              std::isnan(load(fields.nz));
      bool invalid = x || y || z;
      if (invalid && invalid_rows == InvalidRows::nan_point) invalid = (x && y && z) || nan_normal;
      if (!invalid && nan_normal && check_normals) {
        // A point without a normal, as PCL's NormalEstimation leaves one with too few neighbours:
        // kept in place and out of every neighbourhood, like an invalid point. Its coordinates
        // must still be finite (checked here, since the row skips the checks below).
        for (const std::size_t field : position_fields) {
          const double value = load(field);
          if (!std::isfinite(value)) {
            fail(vertex, "coordinate " + element.properties[field].name + " is " + describe_value(value));
          }
        }
        invalid = true;
        ++impl.rows_without_normals;
      }
      if (invalid && !impl.has_invalid_rows) {
        // The rows before the first invalid one were all valid.
        impl.has_invalid_rows = true;
        valid_rows.reserve(element.count);
        for (std::size_t r = 0; r < vertex; ++r) valid_rows.push_back(r);
      }
      if (invalid) {
        row += row_size;
        continue;
      }
      if (impl.has_invalid_rows) valid_rows.push_back(vertex);
    }
    for (const std::size_t field : position_fields) {
      const double value = load(field);
      if (!std::isfinite(value)) {
        fail(vertex, "coordinate " + element.properties[field].name + " is " + describe_value(value));
      }
    }
    if (fields.has_normals() && check_normals) {
      double normal[3];
      for (int axis = 0; axis < 3; ++axis) {
        normal[axis] = load(normal_fields[axis]);
        if (!std::isfinite(normal[axis])) {
          // PCL's NormalEstimation leaves NaN where a point had too few neighbours: say what to do.
          fail(vertex, "normal component " + element.properties[normal_fields[axis]].name + " is " +
                           describe_value(normal[axis]) +
                           (std::isnan(normal[axis]) ? " (as PCL leaves the normal of a point with too few "
                                                       "neighbours; `pnf estimate` computes new normals)"
                                                     : ""));
        }
      }
      if (normal[0] == 0 && normal[1] == 0 && normal[2] == 0) {
        fail(vertex, "the normal is zero-length (0 0 0)");
      }
    }
    row += row_size;
  }
  impl.valid_rows.swap(valid_rows);
}

}  // namespace pnf
