// pnf.PointFile, pnf.read, pnf.write: lossless point files (point_file.hpp).
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "convert.hpp"
#include "pnf/error.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf::python {
namespace {

using namespace pybind11::literals;

const char* format_name(PointFileFormat f) {
  switch (f) {
    case PointFileFormat::ply: return "ply";
    case PointFileFormat::xyz: return "xyz";
    case PointFileFormat::xyzn: return "xyzn";
    case PointFileFormat::pwn: return "pwn";
    case PointFileFormat::pcd: return "pcd";
  }
  return "ply";
}

// A copy of the file's values, made read-only: writing into it would change the copy only and be
// silently lost, so numpy refuses it ("assignment destination is read-only") instead.
py::object read_only(py::object array) {
  array.attr("setflags")("write"_a = false);
  return array;
}

py::object vec3_array(const std::vector<Vec3>& values) {
  Vec3Output out = new_vec3_array(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out.view.set(i, values[i]);
  return read_only(out.array);
}

PointFile from_arrays(py::handle points, py::handle normals, py::handle radii) {
  Vec3Input p(points, "points");
  CloudView view(p.view());
  std::optional<Vec3Input> n;
  if (!normals.is_none()) {
    n.emplace(normals, "normals");
    check_same_size("normals", n->size(), "points", p.size());
    view.normals = n->view();
  }
  std::optional<ScalarInput> r;
  if (!radii.is_none()) {
    r.emplace(radii, "radii");
    check_same_size("radii", r->size(), "points", p.size());
    view.radii = r->view();
  }
  PointFile file(to_point_cloud(view));
  // Zero rows of normals are normals all the same (a PointCloud cannot say so): the file
  // declares nx ny nz, as it does for any other count.
  if (n && !file.has_normals()) file.set_normals({});
  return file;
}

void write_file(const PointFile& file, py::handle path, bool ascii) {
  const std::string p = path_string(path);
  py::gil_scoped_release nogil;
  WriteOptions options;
  options.ascii = ascii;
  write_point_file(p, file, options);
}

py::list elements(const PointFile& file) {
  py::list out;
  for (const PlyElement& e : file.header().elements) {
    py::list properties;
    for (const PlyProperty& p : e.properties) {
      properties.append(p.is_list ? py::make_tuple(p.name, "list " + p.count_type_name + " " + p.type_name)
                                  : py::make_tuple(p.name, p.type_name));
    }
    out.append(py::dict("name"_a = e.name, "count"_a = e.count, "properties"_a = properties));
  }
  return out;
}

// The docstrings help(pnf.PointFile) shows; python/pnf/_pnf.pyi repeats them for type checkers.
constexpr const char* kClassDoc =
    "The contents of a point file, kept whole: every element, property, comment and value.\n\n"
    "PointFile(points, normals=None, radii=None) makes a new one (double x y z [nx ny nz] [radius]);\n"
    "pnf.read(path) reads one. len(f) counts every row of the file; f.points and f.normals hold the\n"
    "points pnf works on, which in a .pcd or .ply can be fewer: rows with NaN coordinates (PCL's\n"
    "invalid pixels) and rows with NaN normals (f.without_normals) stay in the file, in their\n"
    "places, but are not among them.";
constexpr const char* kPointsDoc =
    "(M, 3) float64 positions of the points (M = len(f) less the rows left out, see the class),\n"
    "in file order: a new, read-only array on each access (the file keeps its own types), so\n"
    "f.points[i] = ... raises ValueError instead of being lost; the positions of a PointFile are\n"
    "not changed in place (make a new one: PointFile(points, normals)).";
constexpr const char* kNormalsDoc =
    "(M, 3) float64 normals of the same points, or None: a new, read-only array on each access,\n"
    "so f.normals[i] = ... raises ValueError instead of being lost; to change them, assign a whole\n"
    "array (n = f.normals.copy(); n[i] = ...; f.normals = n). Setting takes one row per row of\n"
    ".points (not len(f)), stores them in the file's declared type (float stays float), adds\n"
    "float nx ny nz to a PLY (normal_x normal_y normal_z to a PCD) that had none, and gives the\n"
    "rows left out NaN normals.";
constexpr const char* kWithoutNormalsDoc =
    "Points with positions but NaN normals (as PCL's NormalEstimation leaves them), left out of\n"
    "points and normals and written back with NaN normals; 0 when read with check_normals=False.";
constexpr const char* kWriteDoc =
    "write(path, *, ascii=False): writes the file, in the format its extension names, with\n"
    "everything it carries. ascii: PLY only, ascii instead of binary little endian (a PCD keeps\n"
    "its DATA encoding). Written to a temporary name and renamed into place; OSError on failure.";

}  // namespace

void bind_point_file(py::module_& m) {
  py::class_<PointFile>(m, "PointFile", kClassDoc)
      .def(py::init(&from_arrays), "points"_a, "normals"_a.none(true) = py::none(), "radii"_a.none(true) = py::none())
      .def("__len__", &PointFile::size, "The number of rows (vertices) of the file, left-out ones included.")
      .def_property_readonly(
          "points", [](const PointFile& f) { return vec3_array(f.cloud().positions); }, kPointsDoc)
      .def_property(
          "normals",
          [](const PointFile& f) -> py::object {
            if (!f.has_normals()) return py::none();
            return vec3_array(f.cloud().normals);
          },
          [](PointFile& f, py::handle normals) {
            // One row per point of .points: invalid points and points without normals are not
            // among them, and keep NaN normals.
            Vec3Input n(normals, "normals");
            check_same_size("normals", n.size(), "points", f.valid_count());
            f.set_normals(to_vectors(n.view()));
          },
          kNormalsDoc)
      .def_property_readonly("without_normals", &PointFile::without_normals, kWithoutNormalsDoc)
      .def_property_readonly(
          "radii",
          [](const PointFile& f) -> py::object {
            PointCloud c = f.cloud();
            if (!c.has_radii()) return py::none();
            py::object np = py::module_::import("numpy");
            return read_only(np.attr("array")(c.radii, "dtype"_a = "float64"));
          },
          "(M,) float64 values of the vertex property `radius` for the points of .points, or None: a\n"
          "new, read-only array on each access.")
      .def_property_readonly(
          "format", [](const PointFile& f) { return format_name(f.source_format()); },
          "\"ply\", \"pcd\", \"xyz\", \"xyzn\" or \"pwn\": what the file was read from.")
      .def_property_readonly(
          "encoding", [](const PointFile& f) { return to_string(f.header().encoding); },
          "\"ascii\", \"binary_little_endian\" or \"binary_big_endian\": a PLY file's encoding (for other\n"
          "formats, that of the equivalent PLY header).")
      .def_property_readonly("elements", &elements,
                             "Each element as {\"name\", \"count\", \"properties\": [(name, type), ...]}.")
      .def_property_readonly(
          "comments",
          [](const PointFile& f) {
            py::list out;
            for (const PlyComment& c : f.header().comments) out.append(c.keyword + " " + c.text);
            return out;
          },
          "The header's comment and obj_info lines.")
      .def("write", &write_file, "path"_a, py::kw_only(), "ascii"_a = false, kWriteDoc)
      .def(
          "copy", [](const PointFile& f) { return PointFile(f); }, "An independent copy.")
      .def("__repr__", [](const PointFile& f) {
        return py::str("<pnf.PointFile {} {} points{}>")
            .format(format_name(f.source_format()), f.size(), f.has_normals() ? " with normals" : "");
      });
  m.def(
      "read",
      [](py::handle path, bool check_normals) {
        const std::string p = path_string(path);
        ReadOptions options;
        options.check_normals = check_normals;
        py::gil_scoped_release nogil;
        return read_point_file(p, options);
      },
      "path"_a, "check_normals"_a);
}

}  // namespace pnf::python
