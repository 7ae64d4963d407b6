// The analysis bindings (docs/python.md, "Analysis"): the welded periodic surface mesh with
// per-vertex curvature, the profile's signed distance and the reader of a run's field file.
// They convert arguments and call the library; no numerics here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "field_array.h"
#include "io/periodic_mesh_file.h"
#include "io/pvti.h"
#include "measure/sharp_surface.h"
#include "mesh/periodic_surface.h"
#include "pipeline/cell_geometry.h"

namespace py = pybind11;

namespace cmcsurf::python {

namespace {

// A real (N, N, N) array indexed [i, j, k] as a whole-grid Field with ghost 2 (the module's
// run functions check N against the multigrid; any N >= 2 meshes).
Field analysis_field(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                     const char* name) {
  if (a.ndim() != 3 || a.shape(0) != a.shape(1) || a.shape(0) != a.shape(2) || a.shape(0) < 4)
    throw py::value_error(
        fmt::format("{}: accepted: a cubic (N, N, N) array of real numbers, N >= 4", name));
  return field_from_cube(a.data(), int(a.shape(0)), name);
}

Field psi_of(const Field& phi) {
  Field psi(phi.n(), 2);
  tanh_profile_inverse(phi, psi);
  return psi;
}

template <class T, std::size_t D>
py::array_t<T> rows(const std::vector<std::array<T, D>>& v) {
  py::array_t<T> out({v.size(), D});
  T* a = out.mutable_data();
  for (std::size_t r = 0; r < v.size(); ++r)
    for (std::size_t c = 0; c < D; ++c) a[r * D + c] = v[r][c];
  return out;
}

py::dict periodic_mesh(const py::array_t<double, py::array::c_style | py::array::forcecast>& phi) {
  const Field f = analysis_field(phi, "phi");
  PeriodicSurfaceMesh m;
  {
    py::gil_scoped_release release;
    m = periodic_surface(psi_of(f));
  }
  py::dict d;
  d["vertices"] = rows(m.vertices);
  std::vector<std::array<std::int64_t, 3>> tri(m.triangles.size());
  py::array_t<std::int64_t> offsets({m.offsets.size(), std::size_t(3), std::size_t(3)});
  std::int64_t* o = offsets.mutable_data();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) tri[t][c] = m.triangles[t][c];
    for (int q = 0; q < 3; ++q)
      for (int c = 0; c < 3; ++c) o[(t * 3 + q) * 3 + c] = m.offsets[t][q][c];
  }
  d["triangles"] = rows(tri);
  d["offsets"] = offsets;
  d["normals"] = rows(m.normals);
  d["mean_curvature"] = py::array_t<double>(m.mean_curvature.size(), m.mean_curvature.data());
  d["gaussian_curvature"] =
      py::array_t<double>(m.gaussian_curvature.size(), m.gaussian_curvature.data());
  d["stats"] = py::module_::import("json").attr("loads")(periodic_mesh_stats_json(m).dump());
  return d;
}

py::array_t<double> signed_distance(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& phi, double epsilon) {
  if (!(epsilon > 0.0 && epsilon < 1.0))
    throw py::value_error(fmt::format("epsilon: got {}; accepted: 0 < E < 1", epsilon));
  return cube_from_field(profile_distance(psi_of(analysis_field(phi, "phi")), epsilon));
}

// Every array of a run folder's field file (field.vti or field.pvti) or of a .vti/.pvti, and
// the file's cmcsurf metadata.
py::dict read_field(const std::filesystem::path& path) {
  const std::filesystem::path file =
      std::filesystem::is_directory(path) ? run_field_file(path) : path;
  VtiReadOptions options;
  options.ghost = 2;
  VtiData data = read_field_file(file, options);
  py::dict arrays;
  for (const auto& [name, field] : data.arrays) arrays[py::str(name)] = cube_from_field(field);
  py::dict out;
  out["file"] = file;
  out["arrays"] = arrays;
  out["metadata"] = data.metadata;
  return out;
}

}  // namespace

void register_analysis(py::module_& m) {
  m.def("periodic_mesh", &periodic_mesh, py::arg("phi"));
  m.def("signed_distance", &signed_distance, py::arg("phi"), py::arg("epsilon"));
  m.def("read_field", &read_field, py::arg("path"));
}

}  // namespace cmcsurf::python
