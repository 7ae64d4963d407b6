// The binding of `cmcsurf scaffold` (driver/scaffold_run.h) and of a unit cell's morphometry:
// arguments arrive as JSON-ready values (cmcsurf/__init__.py checks their types against the
// option table), the library checks their ranges with the command line's messages (ValueError)
// and computes; nothing is computed here.
#include "scaffold.h"

#include <omp.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/pvti.h"
#include "io/vti.h"
#include "multigrid/fas.h"
#include "model/option_checks.h"
#include "model/run_options.h"
#include "driver/scaffold_run.h"

namespace py = pybind11;

namespace cmcsurf::python {

namespace {

nlohmann::json to_json(py::handle v) {
  const std::string text =
      py::str(py::module_::import("json").attr("dumps")(v, py::arg("allow_nan") = false));
  return nlohmann::json::parse(text);
}

py::object to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// OpenMP threads for one call, restored afterwards (threads 0: keep the default).
class Threads {
 public:
  explicit Threads(int threads) : before_(omp_get_max_threads()) {
    if (const std::string why = check_threads(threads); !why.empty())
      throw py::value_error("--threads: " + why);
    if (threads > 0) omp_set_num_threads(threads);
  }
  ~Threads() { omp_set_num_threads(before_); }
  int count() const { return omp_get_max_threads(); }

 private:
  int before_;
};

// A call without the GIL, as module.cpp's run(): `progress` and the signal check take it back;
// a KeyboardInterrupt (Ctrl-C) or an exception raised by `progress` waits in `pending` while
// the library unwinds (ScaffoldContext::stop, then ScaffoldInterrupted), and is raised again.
class Interaction {
 public:
  explicit Interaction(py::object progress) : progress_(std::move(progress)) {}

  void attach(ScaffoldContext& ctx) {
    if (!progress_.is_none())
      ctx.say = [this](const std::string& line) {
        py::gil_scoped_acquire gil;
        try {
          progress_(line);
        } catch (py::error_already_set& e) {
          pending_ = e;
        }
      };
    ctx.stop = [this] {
      py::gil_scoped_acquire gil;
      if (!pending_ && PyErr_CheckSignals() != 0) pending_ = py::error_already_set();
      return pending_.has_value();
    };
  }

  // body() without the GIL; raises what stopped it, or what `progress` raised after the last
  // poll.
  template <class F>
  auto call(F&& body) {
    try {
      auto out = [&] {
        py::gil_scoped_release release;
        return body();
      }();
      if (pending_) throw *pending_;
      return out;
    } catch (const ScaffoldInterrupted&) {
      if (pending_) throw *pending_;
      PyErr_SetNone(PyExc_KeyboardInterrupt);  // a stop without a Python error is one
      throw py::error_already_set();
    }
  }

 private:
  py::object progress_;
  std::optional<py::error_already_set> pending_;
};

// options: the scaffold options given (key -> str, float, int or bool); run_options: the run
// options given (None: the mode chooses); progress: None or a callable taking each line.
// Returns (FILE.json, warnings).
py::tuple scaffold(const py::dict& options, const py::dict& run_options, int threads,
                   const py::object& progress) {
  ScaffoldOptions o;
  const nlohmann::json given = to_json(options);
  for (const ScaffoldOption& option : scaffold_option_table())
    if (given.contains(option.key)) set_scaffold_option(o, option, given.at(option.key));
  for (const auto& [key, value] : given.items())
    if (std::none_of(scaffold_option_table().begin(), scaffold_option_table().end(),
                     [&](const ScaffoldOption& s) { return s.key == key; }))
      throw py::type_error(fmt::format("scaffold() got an unexpected keyword argument '{}'", key));
  RunParams params;
  RunChoices choices;
  const nlohmann::json run_given = to_json(run_options);  // alive while iterated
  for (const auto& [key, value] : run_given.items())
    set_run_option_json(params, choices, key, value);
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw py::type_error(fmt::format("progress: got {}; accepted: None or a callable taking "
                                     "one line (str)", std::string(py::repr(progress))));
  Threads scope(threads);
  ScaffoldContext ctx;
  ctx.threads = scope.count();
  Interaction interaction(progress);
  interaction.attach(ctx);
  const ScaffoldRun run = interaction.call([&] { return make_scaffold(o, params, choices, ctx); });
  return py::make_tuple(to_python(run.report), py::cast(run.warnings));
}

// A C-contiguous float64 (N, N, N) array as a whole-grid field (ghost 2); `name` in errors.
Field cube_field(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                 const char* name) {
  if (a.ndim() != 3 || a.shape(0) != a.shape(1) || a.shape(0) != a.shape(2))
    throw py::value_error(fmt::format("{}: accepted: a cubic (N, N, N) array", name));
  const int n = int(a.shape(0));
  if (const std::string why = check_coarsenable(n); !why.empty())
    throw py::value_error(fmt::format("{}: N = {}: {}", name, n, why));
  Field f(n, 2);
  const double* v = a.data();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = v[(std::size_t(i) * n + j) * n + k];
        if (!std::isfinite(x)) throw py::value_error(fmt::format("{}: holds NaN or inf", name));
        f(i, j, k) = x;
      }
  f.exchange_halo();
  return f;
}

// source: a path (a run folder or a .vti/.pvti field file) or an (N, N, N) array.
py::object morphometry(py::handle source, const std::string& solid, double porosity,
                       double thickness, double cell_size, const std::string& units,
                       int threads) {
  Field phi;
  if (py::isinstance<py::str>(source)) {
    std::filesystem::path path(py::cast<std::string>(source));
    if (std::filesystem::is_directory(path)) path = run_field_file(path);
    if (!std::filesystem::is_regular_file(path))
      throw py::value_error(fmt::format("source: '{}' is neither a run folder with field.vti "
                                        "nor a .vti or .pvti file", path.string()));
    VtiReadOptions read;
    read.ghost = 2;
    read.max_n = kMaxGrid;
    read.only = "phi";
    phi = std::move(read_field_file(path, read).arrays.at("phi"));
  } else {
    phi = cube_field(py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
                         source),
                     "source");
  }
  Threads scope(threads);
  return to_python(cell_morphometry(phi, solid, porosity, thickness, cell_size, units));
}

}  // namespace

void register_scaffold(py::module_& m) {
  m.def("scaffold_options", [] { return to_python(scaffold_option_schema()); });
  m.def("scaffold", &scaffold, py::arg("options"), py::arg("run_options"), py::arg("threads"),
        py::arg("progress"));
  m.def("morphometry", &morphometry, py::arg("source"), py::arg("solid"), py::arg("porosity"),
        py::arg("thickness"), py::arg("cell_size"), py::arg("units"), py::arg("threads"));
}

}  // namespace cmcsurf::python
