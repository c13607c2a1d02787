// pnf._pnf: the pnf library for Python. The public face (names, docstrings, stubs) is the
// package pnf (python/pnf/__init__.py and _pnf.pyi); this file binds the C++ API.
//
// Every call converts its arrays with the GIL held (arrays.hpp says which are read in place),
// then releases the GIL while the library runs.
#include <pybind11/stl.h>

#include <exception>
#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "convert.hpp"
#include "errors.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/options_text.hpp"
#include "pnf/render.hpp"

namespace pnf::python {
namespace {

using namespace pybind11::literals;

// backend= and device= as the CLI's --backend and --device: one parser, pnf::parse_backend_and_device
// (pnf/options_text.hpp), so the same pairs are taken and refused with the same message. None
// for device is the empty text: PNF_DEVICE, then the default rule.
FilterOptions filter_options(const std::optional<std::string>& device, const std::string& backend) {
  FilterOptions options;
  options.device = parse_backend_and_device(backend, device.value_or(""));
  options.validate();
  return options;
}

// The progress callback the library calls after each pass and about every 0.2 s while it builds
// the neighbour lists, within a pass and during --auto's estimate, with the GIL released. It
// takes the GIL back to run Python's signal handlers (so Ctrl-C raises KeyboardInterrupt within
// about 0.2 s) and the user's callable: after a pass only, as callable(pass, passes, seconds),
// unless `every_report` (the callable takes the keywords stage and fraction, which
// python/pnf/__init__.py checks): then at every report, as callable(pass, passes, seconds,
// stage=..., fraction=...) with PassProgress's fields. Any Python exception is kept in `pending`
// and cancels the run; the caller rethrows it in place of pnf::Error(cancelled).
ProgressCallback python_progress(const py::object& callable, bool every_report, std::exception_ptr& pending) {
  // Captures by reference only: the library may copy the std::function without the GIL.
  return [&callable, every_report, &pending](const PassProgress& p) -> bool {
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (callable.is_none()) return true;
      py::object answer;
      if (every_report) {
        using namespace pybind11::literals;
        answer = callable(p.pass, p.passes, p.seconds, "stage"_a = to_string(p.stage), "fraction"_a = p.fraction);
      } else if (p.stage == ProgressStage::pass) {
        answer = callable(p.pass, p.passes, p.seconds);
      }
      // "Returning False cancels": any false value, numpy's np.False_ (a comparison's result)
      // included; None (no return) goes on, as does a report the callable was not called for.
      if (!answer || answer.is_none()) return true;
      const int truth = PyObject_IsTrue(answer.ptr());
      if (truth < 0) throw py::error_already_set();
      return truth != 0;
    } catch (...) {
      pending = std::current_exception();
      return false;
    }
  };
}

// shares_memory's bound on the candidate solutions it tries: strided views of 2-D arrays solve in
// a few; only exotic strides could need more.
constexpr int kOverlapWork = 10000;

// Whether arrays `a` and `b` share an element. numpy's may_share_memory compares address ranges
// only, so the normal columns of one (N, 6) array of positions and normals would overlap its
// position columns; where the ranges meet, shares_memory settles it exactly, within a bounded
// effort (a problem too hard for it counts as an overlap).
bool overlap(const py::object& a, const py::object& b) {
  const py::module_ numpy = py::module_::import("numpy");
  if (!numpy.attr("may_share_memory")(a, b).cast<bool>()) return false;
  try {
    using namespace pybind11::literals;
    return numpy.attr("shares_memory")(a, b, "max_work"_a = kOverlapWork).cast<bool>();
  } catch (const py::error_already_set& e) {
    // numpy.exceptions from numpy 1.25; numpy itself before (Debian 12's is 1.24).
    const py::object exceptions = py::hasattr(numpy, "exceptions") ? numpy.attr("exceptions") : py::object(numpy);
    if (!e.matches(exceptions.attr("TooHardError"))) throw;
    return true;
  }
}

// Runs `body` with the GIL released; a Python exception raised in the progress callback
// replaces the cancellation it caused.
template <typename Body>
void run_released(std::exception_ptr& pending, Body&& body) {
  try {
    py::gil_scoped_release nogil;
    body();
  } catch (const Error& e) {
    if (e.code() == ErrorCode::cancelled && pending) std::rethrow_exception(pending);
    throw;
  }
  if (pending) std::rethrow_exception(pending);
}

const FilterParams kDefaultParams{};

py::object improve_normals(py::handle points, py::handle normals, double sigma_f, double sigma_g, int iterations,
                           const std::string& units, std::optional<double> mean_radius, bool automatic,
                           const std::optional<std::string>& device, const std::string& backend,
                           const py::object& progress, bool progress_stages, py::handle radii,
                           std::optional<double> stop_change_deg, py::handle out_array,
                           std::optional<double> max_seconds) {
  FilterParams params;
  params.sigma_f = sigma_f;
  params.sigma_g = sigma_g;
  params.iterations = iterations;
  params.units = parse_units(units);
  params.mean_radius = mean_radius.value_or(0.0);
  if (automatic) {
    // As `pnf filter --auto`, which refuses these flags: the rule sets all of them.
    if (sigma_f != kDefaultParams.sigma_f || sigma_g != kDefaultParams.sigma_g ||
        iterations != kDefaultParams.iterations || params.units != kDefaultParams.units || mean_radius) {
      throw Error(ErrorCode::invalid_argument,
                  "auto=True chooses sigma_f, sigma_g, iterations, units and mean_radius; do not pass them too");
    }
  }
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw Error(ErrorCode::invalid_argument, "progress must be callable or None");
  }
  params.validate();
  FilterOptions options = filter_options(device, backend);
  if (max_seconds) {
    options.max_seconds = *max_seconds;
    options.validate();
  }

  Vec3Input p(points, "points");
  Vec3Input n(normals, "normals");
  check_same_size("normals", n.size(), "points", p.size());
  std::optional<ScalarInput> r;
  if (!radii.is_none()) {
    r.emplace(radii, "radii");
    check_same_size("radii", r->size(), "points", p.size());
  }
  const CloudView view(p.view(), n.view(), r ? r->view() : ScalarArrayView{});
  // The result goes into `out` when given (it may be the normals themselves: the library reads
  // them before it writes), else into a new array.
  Vec3Output out;
  std::optional<Vec3InOut> given_out;
  if (!out_array.is_none()) {
    given_out.emplace(out_array, "out");
    check_same_size("out", given_out->size(), "points", p.size());
    if (overlap(given_out->array(), p.array())) throw Error(ErrorCode::invalid_argument, "out must not overlap points");
    out.array = py::reinterpret_borrow<py::object>(out_array);
    out.view = given_out->view();
  } else {
    out = new_vec3_array(p.size(), n.result_type());
  }

  std::exception_ptr pending;
  const ProgressCallback callback = python_progress(progress, progress_stages, pending);
  run_released(pending, [&] {
    FilterParams run_params = params;
    NormalFilter filter(options);
    // Reads the caller's arrays in place and writes straight into the result array.
    if (automatic) {  // as `pnf filter --auto`: the rule, then its passes judged
      improve_normals_auto(view, out.view, filter, callback, stop_change_deg ? *stop_change_deg : -1.0);
      return;
    }
    if (stop_change_deg) run_params.stop_change_deg = *stop_change_deg;
    filter.run(view, out.view, run_params, callback);
  });
  return out.array;
}

AutoChoice choose_params(py::handle points, py::handle normals, const std::optional<std::string>& device,
                         const std::string& backend) {
  Vec3Input p(points, "points");
  std::optional<Vec3Input> n;
  if (!normals.is_none()) {
    n.emplace(normals, "normals");
    check_same_size("normals", n->size(), "points", p.size());
  }
  const CloudView view(p.view(), n ? n->view() : Vec3ArrayView{});
  // The device is no longer needed to choose (the passes that auto=True keeps are judged while it
  // filters); a malformed backend or selector is still refused as before, but no device is looked up.
  (void)filter_options(device, backend);
  std::exception_ptr pending;
  AutoChoice choice;
  run_released(pending, [&] { choice = choose_filter_params(view); });
  return choice;
}

py::object estimate(py::handle points, int k, const std::string& orient, const std::array<double, 3>& viewpoint) {
  EstimateParams params;
  params.k = k;
  params.orientation = parse_orientation(orient);
  params.viewpoint = viewpoint;
  params.validate();
  Vec3Input p(points, "points");
  Vec3Output out = new_vec3_array(p.size(), p.result_type());
  // No user callable: the progress reports only run Python's signal handlers, so Ctrl-C raises
  // KeyboardInterrupt during a long estimate.
  std::exception_ptr pending;
  const py::object none = py::none();
  const ProgressCallback callback = python_progress(none, false, pending);
  run_released(pending, [&] { estimate_normals(p.view(), out.view, params, callback); });
  return out.array;
}

RenderMode parse_mode(const std::string& mode) {
  if (mode == "shaded") return RenderMode::shaded;
  if (mode == "normals") return RenderMode::normals;
  if (mode == "error") return RenderMode::error;
  throw Error(ErrorCode::invalid_argument, "mode must be \"shaded\", \"normals\" or \"error\", got \"" + mode + "\"");
}

py::object render(py::handle points, py::handle normals, py::handle radii, int width, int height, double azimuth,
                  double elevation, const std::array<double, 3>& light, const std::string& mode,
                  py::handle reference_normals, double error_max, double radius_scale,
                  const std::optional<std::pair<std::array<double, 3>, std::array<double, 3>>>& frame, int threads) {
  RenderOptions options;
  options.width = width;
  options.height = height;
  options.azimuth_degrees = azimuth;
  options.elevation_degrees = elevation;
  options.light = light;
  options.mode = parse_mode(mode);
  options.error_max_degrees = error_max;
  options.radius_scale = radius_scale;
  if (frame) options.frame = BoundingBox{frame->first, frame->second};
  options.threads = threads;
  options.validate();

  Vec3Input p(points, "points");
  Vec3Input n(normals, "normals");
  check_same_size("normals", n.size(), "points", p.size());
  std::optional<ScalarInput> r;
  if (!radii.is_none()) {
    r.emplace(radii, "radii");
    check_same_size("radii", r->size(), "points", p.size());
  }
  std::optional<Vec3Input> reference;
  if (!reference_normals.is_none()) {
    reference.emplace(reference_normals, "reference_normals");
    check_same_size("reference_normals", reference->size(), "points", p.size());
  }
  const CloudView view(p.view(), n.view(), r ? r->view() : ScalarArrayView{});
  unsigned char* pixels = nullptr;
  py::object image = new_image_array(std::size_t(height), std::size_t(width), &pixels);
  {
    py::gil_scoped_release nogil;
    // The arrays are read in place; the image is drawn once and copied into the numpy array.
    const Image drawn = render_points(view, reference ? reference->view() : Vec3ArrayView{}, options);
    std::copy(drawn.rgb.begin(), drawn.rgb.end(), pixels);
  }
  return image;
}

// For the tests of the no-copy claim: what the binding makes of an array, without running
// anything. The address is the one the library reads.
py::dict view_info(py::handle array) {
  Vec3Input input(array, "array");
  const Vec3ArrayView& v = input.view();
  return py::dict("data"_a = reinterpret_cast<std::uintptr_t>(v.data), "count"_a = v.count,
                  "dtype"_a = to_string(v.type), "row_stride"_a = v.row_step(),
                  "component_stride"_a = v.component_step(), "copied"_a = input.copied());
}

void bind_results(py::module_& m) {
  py::class_<DataEstimate>(m, "DataEstimate",
                           "What choose_params measured (pnf/estimate_data.hpp); lengths in model units.")
      .def_readonly("points", &DataEstimate::points)
      .def_readonly("samples", &DataEstimate::samples)
      .def_readonly("mean_radius", &DataEstimate::mean_radius)
      .def_property_readonly("radius_source",
                             [](const DataEstimate& e) { return std::string(to_string(e.radius_source)); })
      .def_readonly("area_spacing", &DataEstimate::area_spacing)
      .def_readonly("position_noise", &DataEstimate::position_noise)
      .def_readonly("normal_noise_deg", &DataEstimate::normal_noise_deg)
      .def_readonly("normal_noise_neighbours_deg", &DataEstimate::normal_noise_neighbours_deg)
      .def_readonly("normal_noise_chords_deg", &DataEstimate::normal_noise_chords_deg)
      .def_readonly("fit_neighbours", &DataEstimate::fit_neighbours)
      .def_readonly("fit_radius", &DataEstimate::fit_radius)
      .def_readonly("feature_share", &DataEstimate::feature_share)
      .def_readonly("crease_length", &DataEstimate::crease_length)
      .def_readonly("crease_sharpness", &DataEstimate::crease_sharpness)
      .def_readonly("normal_crease_length", &DataEstimate::normal_crease_length)
      .def_readonly("curved_share", &DataEstimate::curved_share)
      .def_readonly("normal_error_correlation", &DataEstimate::normal_error_correlation)
      .def_readonly("normal_position_coupling", &DataEstimate::normal_position_coupling)
      .def_property_readonly("position_noise_area_spacings", &DataEstimate::position_noise_area_spacings)
      .def("__repr__", [](const DataEstimate& e) {
        return py::str(
                   "DataEstimate(points={}, mean_radius={:.6g}, area_spacing={:.6g}, position_noise={:.4g}, "
                   "normal_noise_deg={:.3g}, "
                   "feature_share={:.3f}, curved_share={:.3f})")
            .format(e.points, e.mean_radius, e.area_spacing, e.position_noise, e.normal_noise_deg, e.feature_share,
                    e.curved_share);
      });
  py::class_<AutoChoice>(m, "AutoChoice", "The parameters `pnf filter --auto` picks, and what it measured.")
      .def_property_readonly("sigma_f", [](const AutoChoice& c) { return c.params.sigma_f; })
      .def_property_readonly("sigma_g", [](const AutoChoice& c) { return c.params.sigma_g; })
      .def_property_readonly("iterations", [](const AutoChoice& c) { return c.params.iterations; })
      .def_property_readonly("stop_change_deg", [](const AutoChoice& c) { return c.params.stop_change_deg; })
      .def_property_readonly("units", [](const AutoChoice& c) { return std::string(to_string(c.params.units)); })
      .def_property_readonly("mean_radius", [](const AutoChoice& c) { return c.params.mean_radius; })
      .def_readonly("estimate", &AutoChoice::estimate)
      .def_readonly("rule", &AutoChoice::rule)
      .def_property_readonly("kwargs",
                             [](const AutoChoice& c) {
                               const FilterParams& f = c.params;
                               return py::dict("sigma_f"_a = f.sigma_f, "sigma_g"_a = f.sigma_g,
                                               "iterations"_a = f.iterations, "units"_a = to_string(f.units),
                                               "mean_radius"_a = f.mean_radius,
                                               "stop_change_deg"_a = f.stop_change_deg);
                             })
      .def("__repr__", [](const AutoChoice& c) { return "AutoChoice(" + c.rule + ")"; });
  py::class_<DeviceInfo>(m, "DeviceInfo", "One OpenCL device as the driver reports it (device.hpp).")
      .def_readonly("platform_index", &DeviceInfo::platform_index)
      .def_readonly("device_index", &DeviceInfo::device_index)
      .def_readonly("platform_name", &DeviceInfo::platform_name)
      .def_readonly("platform_vendor", &DeviceInfo::platform_vendor)
      .def_readonly("device_name", &DeviceInfo::device_name)
      .def_readonly("device_vendor", &DeviceInfo::device_vendor)
      .def_readonly("type", &DeviceInfo::type)
      .def_readonly("version", &DeviceInfo::version)
      .def_readonly("driver_version", &DeviceInfo::driver_version)
      .def_readonly("selected", &DeviceInfo::selected)
      .def_property_readonly(
          "selector",
          [](const DeviceInfo& d) { return std::to_string(d.platform_index) + ":" + std::to_string(d.device_index); })
      .def("__repr__", [](const DeviceInfo& d) {
        return py::str("DeviceInfo({}:{} {} '{}' on '{}'{})")
            .format(d.platform_index, d.device_index, d.type, d.device_name, d.platform_name,
                    d.selected ? ", selected" : "");
      });
}

}  // namespace
}  // namespace pnf::python

PYBIND11_MODULE(_pnf, m) {
  namespace py = pybind11;
  using namespace pybind11::literals;
  using namespace pnf::python;
  m.doc() = "pnf C++ bindings; use the package pnf.";
  register_errors(m);
  bind_results(m);
  bind_point_file(m);

  // Defaults and docstrings live once, in python/pnf/__init__.py, which calls these with every argument.
  m.def("improve_normals", &improve_normals, "points"_a, "normals"_a, "sigma_f"_a, "sigma_g"_a, "iterations"_a,
        "units"_a, "mean_radius"_a.none(true), "auto"_a, "device"_a.none(true), "backend"_a, "progress"_a.none(true),
        "progress_stages"_a, "radii"_a.none(true), "stop_change_deg"_a.none(true), "out"_a.none(true),
        "max_seconds"_a.none(true));
  m.def("choose_params", &choose_params, "points"_a, "normals"_a.none(true), "device"_a.none(true), "backend"_a);
  m.def("estimate_normals", &estimate, "points"_a, "k"_a, "orient"_a, "viewpoint"_a);
  m.def(
      "devices",
      [](const std::optional<std::string>& selector) {
        const std::string s = selector.value_or("");
        py::gil_scoped_release nogil;
        return pnf::list_devices(s);
      },
      "selector"_a.none(true));
  m.def("render", &render, "points"_a, "normals"_a, "radii"_a.none(true), "width"_a, "height"_a, "azimuth"_a,
        "elevation"_a, "light"_a, "mode"_a, "reference_normals"_a.none(true), "error_max"_a, "radius_scale"_a,
        "frame"_a.none(true), "threads"_a);
  m.def("_view_info", &view_info, "array"_a);
  // The library's defaults, for the signatures in python/pnf/__init__.py: written once, in
  // pnf::FilterParams and pnf::EstimateParams.
  const pnf::FilterParams filter_defaults{};
  m.attr("FILTER_DEFAULTS") =
      py::dict("sigma_f"_a = filter_defaults.sigma_f, "sigma_g"_a = filter_defaults.sigma_g,
               "iterations"_a = filter_defaults.iterations, "units"_a = pnf::to_string(filter_defaults.units),
               "stop_change_deg"_a = filter_defaults.stop_change_deg, "mean_radius"_a = filter_defaults.mean_radius);
  const pnf::EstimateParams estimate_defaults{};
  m.attr("ESTIMATE_DEFAULTS") =
      py::dict("k"_a = estimate_defaults.k, "orient"_a = pnf::to_string(estimate_defaults.orientation));
}
