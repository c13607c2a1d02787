// pnf.PointFile, pnf.read, pnf.write: lossless point files (point_file.hpp).
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "convert.hpp"
#include "pnf/error.hpp"
#include "pnf/point_file.hpp"

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

py::object vec3_array(const std::vector<Vec3>& values) {
  Vec3Output out = new_vec3_array(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out.view.set(i, values[i]);
  return out.array;
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
  return PointFile(to_point_cloud(view));
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

}  // namespace

void bind_point_file(py::module_& m) {
  py::class_<PointFile>(m, "PointFile")
      .def(py::init(&from_arrays), "points"_a, "normals"_a.none(true) = py::none(), "radii"_a.none(true) = py::none())
      .def("__len__", &PointFile::size)
      .def_property_readonly("points", [](const PointFile& f) { return vec3_array(f.cloud().positions); })
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
          })
      .def_property_readonly("without_normals", &PointFile::without_normals)
      .def_property_readonly("radii",
                             [](const PointFile& f) -> py::object {
                               PointCloud c = f.cloud();
                               if (!c.has_radii()) return py::none();
                               py::object np = py::module_::import("numpy");
                               return np.attr("array")(c.radii, "dtype"_a = "float64");
                             })
      .def_property_readonly("format", [](const PointFile& f) { return format_name(f.source_format()); })
      .def_property_readonly("encoding", [](const PointFile& f) { return to_string(f.header().encoding); })
      .def_property_readonly("elements", &elements)
      .def_property_readonly("comments",
                             [](const PointFile& f) {
                               py::list out;
                               for (const PlyComment& c : f.header().comments) out.append(c.keyword + " " + c.text);
                               return out;
                             })
      .def("write", &write_file, "path"_a, "ascii"_a)
      .def("copy", [](const PointFile& f) { return PointFile(f); })
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
