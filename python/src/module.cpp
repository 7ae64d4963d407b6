// cmcsurf._cmcsurf: the Python binding of the library (python/cmcsurf/__init__.py is its
// Pythonic face). It converts arguments, calls the functions the command line calls and
// converts the results back; it computes nothing itself (docs/python.md).
//
// Index order: a field crosses the boundary as a C-contiguous float64 (N, N, N) array indexed
// [i, j, k] = cell (x_i, y_j, z_k), x_i = (i + 1/2) / N (NumPy's meshgrid(..., indexing="ij")),
// so phi[i, j, k] is Field(i, j, k), and mesh coordinates (x, y, z) follow the same axes.
#include <omp.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <type_traits>
#include <variant>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "common/wall_clock.h"
#include "cahn_hilliard/time_step.h"
#include "io/mesh_output.h"
#include "io/tet_mesh_writers.h"
#include "io/png.h"
#include "io/output_folder.h"
#include "pipeline/properties_stage.h"
#include "science/scattering.h"
#include "io/run_folder.h"
#include "io/run_report.h"
#include "measure/sharp_volume.h"
#include "mesh/scaffold.h"
#include "pipeline/volume_mesh.h"
#include "multigrid/fas.h"
#include "pipeline/cmc.h"
#include "pipeline/member_topology.h"
#include "model/option_checks.h"
#include "pipeline/preview.h"
#include "model/run_options.h"
#include "model/run_schema.h"
#include "driver/run_finish.h"
#include "driver/sweep_driver.h"
#include "pipeline/run_resume.h"
#include "schema/report_schema.h"
#include "pipeline/run_outputs.h"
#include "report/run_page.h"
#include "pipeline/sweep.h"
#include "surfaces/initial.h"
#include "field_array.h"
#include "scaffold.h"

namespace py = pybind11;

namespace cmcsurf::python {

namespace {

constexpr int kMaxGrid = 2048;  // as --grid

// ---- JSON <-> Python -------------------------------------------------------------------

py::object to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// ---- fields <-> arrays -----------------------------------------------------------------

// A copy of the interior as a read-only C-contiguous (N, N, N) float64 array indexed [i, j, k].
py::array_t<double> field_to_array(const Field& f) {
  py::array_t<double> out = cube_from_field(f);
  out.attr("setflags")(py::arg("write") = false);
  return out;
}

// Any real array-like (float16/32/64, integer, unsigned; any strides) as a whole-grid Field
// with ghost 2, converted once to float64. Refuses other dtypes (TypeError), non-cubic shapes,
// N the multigrid cannot coarsen and non-finite values (ValueError), naming `name`.
Field array_to_field(py::handle obj, const char* name) {
  py::object np = py::module_::import("numpy");
  py::array in = py::isinstance<py::array>(obj) ? py::reinterpret_borrow<py::array>(obj)
                                                : py::array(np.attr("asarray")(obj));
  const char kind = in.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(fmt::format(
        "{}: got an array of dtype {}; accepted: real numbers (float or integer dtypes, "
        "converted to float64)",
        name, std::string(py::str(in.dtype()))));
  if (in.ndim() != 3 || in.shape(0) != in.shape(1) || in.shape(0) != in.shape(2)) {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < in.ndim(); ++d)
      shape += fmt::format("{}{}", d ? ", " : "", in.shape(d));
    shape += in.ndim() == 1 ? ",)" : ")";
    throw py::value_error(fmt::format(
        "{}: got shape {}; accepted: a cubic (N, N, N) array, N = m 2^k with m in "
        "{{1,3,5,7}}, 8 <= N <= {}",
        name, shape, kMaxGrid));
  }
  const py::ssize_t n64 = in.shape(0);
  if (n64 > kMaxGrid)
    throw py::value_error(
        fmt::format("{}: got N = {}; accepted: N <= {}", name, n64, kMaxGrid));
  const int n = int(n64);
  if (const std::string why = check_coarsenable(n); !why.empty())
    throw py::value_error(fmt::format("{}: shape ({}, {}, {}): {}", name, n, n, n, why));
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
  if (!a) throw py::error_already_set();
  return field_from_cube(a.data(), n, name);
}

// ---- options ---------------------------------------------------------------------------

// Every keyword argument of the module goes through one of the four conversions below (real,
// integer, string, bool), so that each refuses the same things the same way: a value of
// another kind is a TypeError "epsilon: got '0.05' of type str; accepted: a real number" (None
// included: where None means "not given" the caller skips it), and the value's range is the
// library's check with the command line's message (ValueError).

std::string type_name(py::handle v) {
  return std::string(py::str(py::type::of(v).attr("__name__")));
}

[[noreturn]] void wrong_type(py::handle v, const std::string& key, const char* type) {
  throw py::type_error(fmt::format("{}: got {} of type {}; accepted: {}", key,
                                   std::string(py::repr(v)), type_name(v), type));
}

bool is_bool(py::handle v) {
  return py::isinstance<py::bool_>(v) ||
         py::isinstance(v, py::module_::import("numpy").attr("bool_"));
}

// int, float and NumPy scalars (numbers.Real); not bool, str, bytes or an array (a NumPy
// array of one element converts to float, but it is no number).
bool is_number(py::handle v, const char* abc) {
  return !is_bool(v) && py::isinstance(v, py::module_::import("numbers").attr(abc));
}

double real_option(py::handle v, const std::string& key) {
  if (!is_number(v, "Real")) wrong_type(v, key, "a real number");
  try {
    return py::float_(py::reinterpret_borrow<py::object>(v));
  } catch (const py::error_already_set& e) {
    // An int beyond double: infinite, which every range check refuses.
    if (!e.matches(PyExc_OverflowError)) throw;
    return py::int_(py::reinterpret_borrow<py::object>(v)) < py::int_(0)
               ? -std::numeric_limits<double>::infinity()
               : std::numeric_limits<double>::infinity();
  }
}

// An integer as long long, saturated (2^70 -> 2^63 - 1); `given` is the user's value then.
long long integer_option(py::handle v, const std::string& key, std::string* given) {
  if (!is_number(v, "Integral")) wrong_type(v, key, "an integer");
  const py::int_ i = py::module_::import("operator").attr("index")(v);
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow == 0) return x;
  *given = py::str(py::object(i)).cast<std::string>();
  return overflow > 0 ? std::numeric_limits<long long>::max()
                      : std::numeric_limits<long long>::min();
}

std::string string_option(py::handle v, const std::string& key) {
  if (!py::isinstance<py::str>(v)) wrong_type(v, key, "a string");
  std::string s = py::cast<std::string>(v);
  if (s.find('\0') != std::string::npos)
    throw py::value_error(fmt::format("{}: got {}, which holds a NUL character; accepted: a "
                                      "string without NUL characters",
                                      key, std::string(py::repr(v))));
  return s;
}

bool bool_option(py::handle v, const std::string& key) {
  if (!is_bool(v))
    throw py::type_error(
        fmt::format("{}: got {}; accepted: True or False", key, std::string(py::repr(v))));
  return py::cast<bool>(v);
}

// A path: str or os.PathLike (str), without NUL characters.
std::filesystem::path path_option(py::handle v, const std::string& key) {
  py::object s = py::reinterpret_borrow<py::object>(v);
  if (!py::isinstance<py::str>(v)) {
    if (!py::hasattr(v, "__fspath__")) wrong_type(v, key, "a str or os.PathLike path");
    s = py::module_::import("os").attr("fspath")(v);
    if (!py::isinstance<py::str>(s)) wrong_type(v, key, "a str or os.PathLike path");
  }
  return std::filesystem::path(string_option(s, key));
}

// A list: a str as the command line takes it ("P,D,G"), or a sequence (not bytes) whose
// elements are converted one by one, named "surfaces[1]", and joined with commas.
std::string list_option(py::handle v, const std::string& key, const char* accepted,
                        const std::function<std::string(py::handle, const std::string&)>& item) {
  if (py::isinstance<py::str>(v)) return string_option(v, key);
  if (py::isinstance<py::bytes>(v) || !py::isinstance<py::sequence>(v))
    wrong_type(v, key, accepted);
  std::string out;
  std::size_t i = 0;
  for (py::handle e : v) {
    if (i > 0) out += ',';
    out += item(e, fmt::format("{}[{}]", key, i));
    ++i;
  }
  return out;
}

// A library message about a saturated value, with the user's value in its place:
// "--threads: got 9223372036854775807; ..." -> "--threads: got 1180591620717411303424; ...".
// An empty `given`: the value was not saturated, the message stays.
std::string with_given(std::string message, long long shown, const std::string& given) {
  if (given.empty()) return message;
  const std::string got = fmt::format("got {}", shown);
  if (const auto at = message.find(got); at != std::string::npos)
    message.replace(at, got.size(), "got " + given);
  return message;
}

// threads=T: an integer, checked as --threads is (model/option_checks.h).
int threads_option(py::handle v) {
  std::string given;
  const long long t = integer_option(v, "threads", &given);
  if (const std::string why = check_threads(t); !why.empty())
    throw py::value_error("--threads: " + with_given(why, t, given));
  return int(t);
}

// seed=S: 0 <= S < 2^64 as --seed (the sign is check_seed's, model/option_checks.h).
unsigned long long seed_option(py::handle v) {
  if (!is_number(v, "Integral")) wrong_type(v, "seed", "an integer");
  const py::int_ seed = py::module_::import("operator").attr("index")(v);
  if (seed < py::int_(0) || seed > py::int_(std::numeric_limits<unsigned long long>::max()))
    throw py::value_error(
        "--seed: " + with_given(check_seed(-1), -1, py::str(py::object(seed)).cast<std::string>()));
  return seed.cast<unsigned long long>();
}

// The int options that were beyond int: the run takes the nearest int (what the library's
// range checks then see) and the message names the user's value.
class IntOptions {
 public:
  int take(py::handle v, const std::string& key) {
    std::string given;
    const long long x = integer_option(v, key, &given);
    const int clamped = int(std::clamp<long long>(x, std::numeric_limits<int>::min(),
                                                  std::numeric_limits<int>::max()));
    if (clamped != x && beyond_.empty()) {
      beyond_ = key;
      given_ = given.empty() ? std::to_string(x) : given;
      clamped_ = clamped;
    }
    return clamped;
  }
  // After the library's checks: its message about the clamped value names the user's value;
  // a clamped value it accepted (max_steps=2**40) is refused here, as the command line refuses
  // a number beyond int.
  [[noreturn]] void refuse(const std::string& message) const {
    throw py::value_error(beyond_.empty() ? message : with_given(message, clamped_, given_));
  }
  void check_accepted() const {
    if (beyond_.empty()) return;
    throw py::value_error(fmt::format("{}: got {}; accepted: an int (|n| < 2^31) in the range "
                                      "of its option (`cmcsurf run --help`)",
                                      beyond_, given_));
  }

 private:
  std::string beyond_, given_;
  int clamped_ = 0;
};

// The keyword arguments of run(): the run option table's keys (model/run_schema.h), each
// converted by its type. None means "not given" only for the options --fast or --paper chooses
// (and is a TypeError elsewhere); a key that is absent is not given. Unknown keys are a
// TypeError, as in any Python call.
void apply_options(RunParams& p, RunChoices& c, IntOptions& ints, const py::dict& options) {
  for (auto [key_obj, v] : options) {
    const std::string key = py::cast<std::string>(key_obj);
    const RunOption* o = find_run_option(key);
    if (o == nullptr || !o->python())
      throw py::type_error(fmt::format("unexpected keyword argument '{}'", key));
    if ((o->fast != nullptr || o->paper != nullptr) && v.is_none()) continue;  // a mode chooses
    std::visit(
        [&](const auto& ref) {
          using R = std::decay_t<decltype(ref)>;
          if constexpr (std::is_same_v<R, RunChoice>) {
            c.text[key] = string_option(v, key);
          } else if constexpr (std::is_same_v<R, RunMember<std::uint64_t>>) {
            ref(p) = seed_option(v);
          } else {
            auto& x = ref(p);
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, double>) x = real_option(v, key);
            else if constexpr (std::is_same_v<T, int>) x = ints.take(v, key);
            else if constexpr (std::is_same_v<T, bool>) x = bool_option(v, key);
            else x = string_option(v, key);
          }
        },
        o->ref);
    c.given.insert(key);
  }
}

// The run option table for the Python package (cmcsurf/__init__.py builds the signatures of
// run, relax and sweep from it): key, command-line name, scope, default, unit, help, accepted
// range, and whether --fast or --paper chooses it (then the keyword's default is None).
py::list run_option_schema() {
  const RunParams defaults;
  const nlohmann::json values = params_json(defaults);
  py::list out;
  for (const RunOption& o : run_option_table()) {
    if (!o.python()) continue;
    static const char* const kScopes[] = {"surface", "initial", "grid", "solver", "internal"};
    py::dict d;
    d["key"] = o.key;
    d["cli"] = o.name();
    d["scope"] = kScopes[int(o.scope)];
    d["default"] = to_python(values.at(o.key));
    d["unit"] = o.unit;
    d["help"] = o.help;
    d["accepted"] = std::holds_alternative<RunChoice>(o.ref) ? run_choice_names(o)
                                                              : std::string(o.accepted);
    d["fast"] = o.fast != nullptr;
    d["paper"] = o.paper != nullptr;
    d["type"] = std::visit(
        [](const auto& ref) -> std::string {
          using R = std::decay_t<decltype(ref)>;
          if constexpr (std::is_same_v<R, RunMember<double>>) return "float";
          else if constexpr (std::is_same_v<R, RunMember<bool>>) return "bool";
          else if constexpr (std::is_same_v<R, RunMember<int>> ||
                             std::is_same_v<R, RunMember<std::uint64_t>>) return "int";
          else return "str";
        },
        o.ref);
    out.append(d);
  }
  return out;
}

// The options converted and checked as the command line's (finish_run_params); `adjust` may
// change them before the checks (measure() and relax() set the grid from their field).
RunParams run_params(const py::dict& options, bool check_surface,
                     const std::function<void(RunParams&)>& adjust = {}) {
  RunParams p;
  RunChoices c;
  IntOptions ints;
  apply_options(p, c, ints, options);
  if (adjust) adjust(p);
  try {
    finish_run_params(p, c, check_surface);
  } catch (const OptionError& e) {
    ints.refuse(e.what());
  }
  ints.check_accepted();
  return p;
}

// A run that cannot fit in the memory this process may still take raises MemoryError now,
// naming the figures (model/run_options.h), instead of failing after the solve.
void refuse_if_too_large(const RunParams& p) {
  if (const std::string why = check_run_memory(p); !why.empty()) {
    PyErr_SetString(PyExc_MemoryError, why.c_str());
    throw py::error_already_set();
  }
}

// OpenMP threads for one call (0: keep OMP_NUM_THREADS or all cores), restored afterwards so
// that a later call with threads=0 gets the default again. The solve runs on this thread.
class ThreadScope {
 public:
  explicit ThreadScope(py::handle threads) : before_(omp_get_max_threads()) {
    const int t = threads_option(threads);
    if (t > 0) omp_set_num_threads(t);
  }
  ~ThreadScope() { omp_set_num_threads(before_); }
  int count() const { return omp_get_max_threads(); }

 private:
  int before_;
};

// ---- the solve with the GIL released ----------------------------------------------------

// A Python exception (KeyboardInterrupt from Ctrl-C, or one raised by `progress`) waits in
// Interaction::pending while the run unwinds.
struct PythonPending : std::exception {};

// history.csv's columns of one step (in its order, schema/report_schema.h), and in a sweep the
// member it belongs to.
py::dict step_dict(const StepRecord& r, const std::string& member) {
  py::dict d;
  for (const HistoryColumnInfo& c : history_column_table())
    d[py::str(std::string(c.name))] =
        std::visit([](const auto& v) { return py::cast(v); }, history_value(r, c.id));
  if (!member.empty()) d["member"] = member;
  return d;
}

// The run's context: `progress` (with the GIL) after every step, and a signal check before
// every step (RunContext::control) and after it, so Ctrl-C stops the run within a step.
class Interaction {
 public:
  explicit Interaction(py::object progress) : progress_(std::move(progress)) {
    if (!progress_.is_none() && !PyCallable_Check(progress_.ptr()))
      throw py::type_error(fmt::format(
          "progress: got {}; accepted: None or a callable taking one dict per time step",
          std::string(py::repr(progress_))));
  }

  // A sweep's member from now on (its name goes into the progress dicts).
  void set_member(const std::string& name) { member_ = name; }

  // The sweep driver's hooks (driver/sweep_driver.h), called without the GIL; they must not
  // throw through the driver, so a Python error waits in `pending` and the next stop check
  // stops the member there, leaving its checkpoint as a signal does.
  void step(const StepRecord& r) {
    py::gil_scoped_acquire gil;
    if (progress_.is_none() || pending_) return;
    try {
      progress_(step_dict(r, member_));
    } catch (py::error_already_set& e) {
      pending_ = e;
    }
  }
  bool stop_requested() {
    py::gil_scoped_acquire gil;
    return poll();
  }
  // What stopped the sweep, for the interrupted member's report.json ("signal").
  std::string stop_name() {
    py::gil_scoped_acquire gil;
    if (pending_ && pending_->matches(PyExc_KeyboardInterrupt)) return "SIGINT";
    return "a Python exception in progress";
  }
  // Re-raises what stopped a sweep, if anything did.
  void raise_pending() {
    if (pending_) throw *pending_;
  }

  RunContext context() {
    RunContext c;
    c.progress = [this](const StepRecord& r) {
      py::gil_scoped_acquire gil;
      if (!progress_.is_none()) {
        try {
          progress_(step_dict(r, member_));
        } catch (py::error_already_set& e) {
          pending_ = e;
          throw PythonPending{};
        }
      }
      if (poll()) throw PythonPending{};
    };
    c.control = [this]() {
      py::gil_scoped_acquire gil;
      return poll() ? RunControl::kStop : RunControl::kContinue;
    };
    return c;
  }

  // Runs body(context) without the GIL; re-raises what stopped it.
  template <class F>
  auto solve(F&& body) {
    using R = decltype(body(std::declval<const RunContext&>()));
    std::optional<R> out;
    const RunContext c = context();
    try {
      py::gil_scoped_release release;
      out.emplace(body(c));
    } catch (const PythonPending&) {
    } catch (const RunInterrupted&) {
    }
    if (pending_) throw *pending_;
    if (!out) {  // stopped without a Python error: report it as the interruption it was
      PyErr_SetNone(PyExc_KeyboardInterrupt);
      throw py::error_already_set();
    }
    return std::move(*out);
  }

 private:
  // With the GIL: runs the Python signal handlers (main thread only); true when one raised.
  bool poll() {
    if (pending_) return true;
    if (PyErr_CheckSignals() != 0) {
      pending_ = py::error_already_set();
      return true;
    }
    return false;
  }

  py::object progress_;
  std::string member_;
  std::optional<py::error_already_set> pending_;
};

py::object to_path(const std::filesystem::path& p) {
  return py::module_::import("pathlib").attr("Path")(p.string());
}

// ---- results ---------------------------------------------------------------------------

// report.json keys of a run the command line adds (cmd_run.cpp): the process layout, and the
// checkpoints, of which a Python run writes none (Ctrl-C raises instead).
nlohmann::json single_run_extra() {
  nlohmann::json extra = decomposition_json(*Decomposition::world());
  extra["checkpoints_written"] = 0;
  extra["checkpoint_seconds"] = 0.0;
  return extra;
}

// A run's configuration, result and quality stage, immutable once made; report() is the
// report.json of the same run from the command line.
struct Result {
  RunParams params;
  RunResult result;
  CmcQuality quality;
  int threads = 1;
  nlohmann::json extra;  // keys the command line adds (process layout, checkpoints, member)
  nlohmann::json report;
  py::object phi_cache, report_cache, history_cache;

  // The final measures' psi and samples that the run returned beside its result, until finish().
  std::optional<FinalFieldCache> cache;

  Result(const RunParams& p, RunResult r, int t, nlohmann::json x, FinalFieldCache c)
      : params(p), result(std::move(r)), threads(t), extra(std::move(x)), cache(std::move(c)) {}
  // A sweep member the driver finished: its quality stage ran and its report.json is written.
  Result(const RunParams& p, RunResult r, int t, nlohmann::json x, CmcQuality q,
         nlohmann::json written)
      : params(p), result(std::move(r)), quality(std::move(q)), threads(t), extra(std::move(x)),
        report(std::move(written)) {}

  // The quality stage (measure_cmc_quality), then the report: what `cmcsurf run` does after
  // the solve.
  void finish() {
    // The final measures' psi and samples when the run kept them; then they are let go.
    const bool kept = cache && cache->psi.n() == result.phi.n();
    const Field psi = kept ? std::move(cache->psi) : profile_inverse(result.phi);
    quality = run_quality(psi, params, result, kept ? &cache->samples : nullptr);
    cache.reset();
    report = run_folder_report(params, result, quality, threads, extra);
  }

  py::object phi() {
    if (!phi_cache) phi_cache = field_to_array(result.phi);
    return phi_cache;
  }
  py::object report_dict() {
    if (!report_cache) report_cache = to_python(report);
    return report_cache;
  }
  py::object history() {
    if (history_cache) return history_cache;
    const auto& h = result.history;
    const std::size_t n = h.size();
    py::dict d;
    for (const HistoryColumnInfo& c : history_column_table()) {
      const py::str name(std::string(c.name));
      if (c.type == HistoryType::kText) {
        py::list text;
        for (std::size_t s = 0; s < n; ++s)
          text.append(std::get<std::string>(history_value(h[s], c.id)));
        d[name] = py::module_::import("numpy").attr("array")(text, py::arg("dtype") = "str");
      } else if (c.type == HistoryType::kInt) {
        py::array_t<long long> column(n);
        for (std::size_t s = 0; s < n; ++s)
          column.mutable_at(s) = std::get<long long>(history_value(h[s], c.id));
        d[name] = column;
      } else {
        py::array_t<double> column(n);
        for (std::size_t s = 0; s < n; ++s)
          column.mutable_at(s) = std::get<double>(history_value(h[s], c.id));
        d[name] = column;
      }
    }
    history_cache = d;
    return d;
  }
  // The run folder as `cmcsurf run --out dir` writes it: the preview stage and preview.png
  // (--no-preview: preview=False), write_run_folder, then report.html (--no-report:
  // report=False) from the folder's files, as the CLI does.
  py::object save(py::handle dir_arg, py::handle float32_arg, py::handle preview_arg,
                  py::handle report_arg, py::handle force_arg) {
    const std::filesystem::path dir = path_option(dir_arg, "dir");
    const bool float32 = bool_option(float32_arg, "float32");
    const bool preview = bool_option(preview_arg, "preview");
    const bool page = bool_option(report_arg, "report");
    const bool force = bool_option(force_arg, "force");
    {
      py::gil_scoped_release release;
      // Ours, or new or empty, and one writer at a time (io/output_folder.h); before any work.
      FolderClaim claim;
      try {
        claim = claim_output_folder(dir, {.kind = "run", .option = "dir", .force = force});
      } catch (const FolderRefused& e) {
        if (e.usage()) throw py::value_error(e.what());
        throw;
      }
      // The pictures of the quality stage that ran with the run, then the folder as the
      // command line finishes it (driver/run_finish.h).
      RunOutputs outputs = run_pictures(params, result, quality, preview, page);
      RunFolderOptions o;
      o.threads = threads;
      o.float32 = float32;
      o.remove_checkpoint = false;  // a Python run writes none
      finish_run_folder(dir, params, result, outputs, o, extra);
    }
    return to_path(dir);
  }
};

struct Mesh {
  TriMesh mesh;
  nlohmann::json report;
  ScaffoldParams params;
  std::string source;  // FILE.json's "source", as `cmcsurf mesh --from` records its field's
  py::object vertices_cache, faces_cache, report_cache;

  py::object vertices() {
    if (vertices_cache) return vertices_cache;
    const std::size_t n = mesh.vertices.size();
    py::array_t<double> v({n, std::size_t(3)});
    double* a = v.mutable_data();
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) a[3 * i + c] = mesh.vertices[i][c];
    v.attr("setflags")(py::arg("write") = false);
    return vertices_cache = v;
  }
  py::object faces() {
    if (faces_cache) return faces_cache;
    const std::size_t m = mesh.triangles.size();
    py::array_t<std::int64_t> f({m, std::size_t(3)});
    std::int64_t* a = f.mutable_data();
    for (std::size_t i = 0; i < m; ++i)
      for (int c = 0; c < 3; ++c) a[3 * i + c] = mesh.triangles[i][c];
    f.attr("setflags")(py::arg("write") = false);
    return faces_cache = f;
  }
  py::object report_dict() {
    if (!report_cache) report_cache = to_python(report);
    return report_cache;
  }
  // The mesh file and FILE.json, as `cmcsurf mesh --out path` writes them.
  py::object save(py::handle path_arg, py::handle format_arg) {
    const std::filesystem::path path = path_option(path_arg, "path");
    MeshPlan plan;
    plan.params = params;
    plan.out = path;
    plan.format = mesh_output_format(string_option(format_arg, "format"), path);
    {
      py::gil_scoped_release release;
      write_mesh_with_report(mesh, report, plan, {{"source", source}});
    }
    return to_path(path);
  }
};

// ---- the functions ---------------------------------------------------------------------

std::shared_ptr<Result> run(const py::dict& options, py::handle threads, py::object progress) {
  const RunParams p = run_params(options, true);
  refuse_if_too_large(p);
  ThreadScope scope(threads);
  Interaction ia(std::move(progress));
  auto out = ia.solve([&](const RunContext& c) {
    FinalFieldCache cache;
    RunResult result = run_cmc(p, c, &cache);
    auto r = std::make_shared<Result>(p, std::move(result), scope.count(), single_run_extra(),
                                      std::move(cache));
    r->finish();
    return r;
  });
  return out;
}

std::shared_ptr<Result> relax(py::handle phi, py::handle volume_fraction_arg,
                              py::handle algorithm_arg, const py::dict& options,
                              py::handle threads, py::object progress) {
  std::optional<double> volume_fraction;  // None: phi's own
  if (!volume_fraction_arg.is_none())
    volume_fraction = real_option(volume_fraction_arg, "volume_fraction");
  const std::string algorithm = string_option(algorithm_arg, "algorithm");
  const Field start = array_to_field(phi, "phi");
  py::dict o = options;
  if (!o.contains("surface") || o["surface"].is_none()) o["surface"] = "field";
  o["grid"] = start.n();
  RunParams p = run_params(o, false);
  if (o.contains("coarse_levels") && !o["coarse_levels"].is_none() && p.coarse_levels != 0)
    throw py::value_error("--coarse-levels: relax() starts from the given field on its own "
                          "grid; accepted: 0");
  p.coarse_levels = 0;
  refuse_if_too_large(p);
  nlohmann::json extra = single_run_extra();
  const bool cmc = algorithm == "cmc";
  if (!cmc && algorithm != "direct")
    throw py::value_error(
        fmt::format("algorithm: got '{}'; accepted: cmc, direct", algorithm));
  if (cmc) {
    // The target: the given one, or the field's own sharp volume fraction of {phi > 1/2}.
    const double alpha = volume_fraction ? *volume_fraction : sharp_volume_fraction(start);
    if (!(alpha > 0.0 && alpha < 1.0))
      throw py::value_error(
          volume_fraction
              ? fmt::format("--volume-fraction: got {}; accepted: 0 < A < 1", alpha)
              : fmt::format("phi: its volume fraction of phi > 1/2 is {}, so there is no "
                            "surface to relax; accepted: a field with both phases",
                            alpha));
    p.volume_fraction = alpha;
    extra["volume_fraction_target"] = alpha;
  } else if (volume_fraction) {
    throw py::value_error("volume_fraction: algorithm='direct' keeps the field's own mass; "
                          "accepted: None, or algorithm='cmc'");
  }
  ThreadScope scope(threads);
  Interaction ia(std::move(progress));
  return ia.solve([&](const RunContext& c) {
    FinalFieldCache cache;
    RunResult r = cmc ? run_cmc_from_field(start, p, c, &cache) : relax_field(start, p, c, &cache);
    auto out = std::make_shared<Result>(p, std::move(r), scope.count(), extra, std::move(cache));
    out->finish();
    return out;
  });
}

py::array_t<double> initial_field(const py::dict& options) {
  const RunParams p = run_params(options, true);
  InitialFieldParams init;
  init.surface = p.surface;
  init.epsilon = p.epsilon;
  init.radius = p.radius;
  init.seed = p.seed;
  init.noise_amplitude = p.noise_amplitude;
  return field_to_array(make_initial_field(init, p.grid, 2));
}

// options: epsilon and surface (None: not given), checked as run()'s are.
py::object measure(py::handle phi, const py::dict& options, py::handle threads) {
  Field f = array_to_field(phi, "phi");
  py::dict o = options;
  const bool named = o.contains("surface") && !o["surface"].is_none();  // None: not given
  if (!named && o.contains("surface")) PyDict_DelItemString(o.ptr(), "surface");
  const RunParams p = run_params(o, named, [&](RunParams& q) {
    q.grid = f.n();
    if (!named) q.surface = "field";
  });  // --epsilon, --surface
  ThreadScope scope(threads);
  nlohmann::json j;
  {
    py::gil_scoped_release release;
    const Measures m = measure_field(f, p.epsilon);
    const CmcQuality q = measure_cmc_quality(f, p);
    j = measures_json(m);
    j.update(quality_json(q, m.area));
    j["grid"] = p.grid;
    j["epsilon"] = p.epsilon;
  }
  return to_python(j);
}

// The sweep's members and run options, checked as `cmcsurf sweep`'s.
SweepParams sweep_params(py::handle surfaces_arg, py::handle fractions_arg,
                         py::handle continuation, const py::dict& options) {
  const std::string surfaces =
      list_option(surfaces_arg, "surfaces", "a str \"P,D,G\" or a sequence of str",
                  [](py::handle e, const std::string& key) { return string_option(e, key); });
  const std::string fractions = list_option(
      fractions_arg, "volume_fractions",
      "a str \"start:stop:step\" or \"a,b,c\", or a sequence of real numbers",
      [](py::handle e, const std::string& key) {
        return fmt::format("{}", real_option(e, key));  // shortest text that reads back equal
      });
  SweepParams sp;
  sp.run = run_params(options, false);
  try {
    sp.surfaces = parse_surface_list(surfaces);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(fmt::format("--surface: {}", e.what()));
  }
  try {
    sp.fractions = parse_volume_fractions(fractions);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(fmt::format("--volume-fractions: {}", e.what()));
  }
  sp.continuation = bool_option(continuation, "continuation");
  try {
    check_sweep_params(sp);  // members with one name (G,G or 0.5,0.5)
  } catch (const std::invalid_argument& e) {
    throw py::value_error(fmt::format("surfaces, volume_fractions: {}", e.what()));
  }
  return sp;
}

// The columns of sweep.csv of `reports`, in its order.
std::vector<std::string> sweep_columns(const std::vector<nlohmann::json>& reports) {
  const std::string csv = sweep_csv(reports);
  const std::string header = csv.substr(0, csv.find('\n'));
  std::vector<std::string> columns;
  for (std::size_t pos = 0; pos <= header.size();) {
    const std::size_t comma = std::min(header.find(',', pos), header.size());
    columns.push_back(header.substr(pos, comma - pos));
    pos = comma + 1;
  }
  return columns;
}

py::tuple sweep(py::handle surfaces_arg, py::handle fractions_arg, py::handle continuation,
                const py::dict& options, py::handle threads, py::object progress) {
  const SweepParams sp = sweep_params(surfaces_arg, fractions_arg, continuation, options);
  refuse_if_too_large(sp.run);
  ThreadScope scope(threads);
  Interaction ia(std::move(progress));
  std::vector<std::shared_ptr<Result>> results;
  std::vector<nlohmann::json> reports;
  ia.solve([&](const RunContext& c) {
    run_sweep(
        sp, [&](const SweepMember& m) { ia.set_member(m.name); },
        [&](const SweepMember& m, RunResult r, FinalFieldCache cache) {
          auto res = std::make_shared<Result>(
              m.params, std::move(r), scope.count(),
              nlohmann::json{{"volume_fraction_target", m.alpha},
                             {"member", m.name},
                             {"started_from", m.started_from}},
              std::move(cache));
          res->finish();
          reports.push_back(res->report);
          results.push_back(res);
        },
        c);
    return 0;
  });
  return py::make_tuple(results, sweep_columns(reports));
}

// The keyword arguments of mesh() (`cmcsurf mesh`'s options with '_' for '-'; None: not
// given), type-checked as run()'s; their ranges are scaffold_params's (io/mesh_output.h).
MeshOutputOptions mesh_options(const py::dict& options) {
  MeshOutputOptions o;
  for (auto [key_obj, v] : options) {
    const std::string key = py::cast<std::string>(key_obj);
    if (key == "tile") o.tile = string_option(v, key);
    else if (key == "cell_size") o.cell_size = real_option(v, key);
    else if (key == "units") o.units = string_option(v, key);
    else if (key == "solid") o.solid = string_option(v, key);
    else if (key == "thickness") {
      if (!v.is_none()) o.thickness = real_option(v, key);  // None: not given
    }
    else if (key == "other_phase") o.other_phase = bool_option(v, key);
    else if (key == "keep_fragments") o.keep_fragments = bool_option(v, key);
    else if (key == "accept_topology_change") o.accept_topology_change = bool_option(v, key);
    else throw py::type_error(fmt::format("unexpected keyword argument '{}'", key));
  }
  return o;
}

std::shared_ptr<Mesh> mesh(py::handle source, const py::dict& options, py::handle threads) {
  std::optional<Field> owned;
  const Field* phi = nullptr;
  auto out = std::make_shared<Mesh>();
  if (py::isinstance<Result>(source)) {
    const Result& r = py::cast<Result&>(source);
    phi = &r.result.phi;
    out->source = fmt::format("cmcsurf.Result: {}, volume fraction {:.6g}, grid {}",
                              r.params.surface, r.result.final.volume_fraction, r.params.grid);
  } else {
    owned = array_to_field(source, "phi");
    phi = &*owned;
    out->source = fmt::format("array of shape ({n}, {n}, {n})", fmt::arg("n", phi->n()));
  }
  const MeshOutputOptions o = mesh_options(options);
  out->params = scaffold_params(o, phi->n());
  if (py::isinstance<Result>(source) && !o.accept_topology_change) {
    // A member of another topology than its family's (pipeline/member_topology.h).
    const Result& r = py::cast<Result&>(source);
    if (r.result.euler_characteristic_start && r.result.final.sharp)
      check_member_topology({r.params.surface, r.params.volume_fraction,
                             r.result.final.euler_characteristic,
                             *r.result.euler_characteristic_start},
                            "cmcsurf.Result", "accept_topology_change=True");
  }
  ThreadScope scope(threads);
  {
    py::gil_scoped_release release;
    Scaffold s = build_scaffold(*phi, out->params);
    out->mesh = std::move(s.mesh);
    out->report = std::move(s.report);
  }
  return out;
}

// cmcsurf volume-mesh of a Result or an (N, N, N) field (pipeline/volume_mesh.h): writes `out`
// and out.json as the command does and returns the report. options: solid, porosity,
// thickness, tile, cell_size, units, size, size_min, size_max, facet_distance, cut, format
// (None: not given).
py::object volume_mesh(py::handle source, const std::string& out, const py::dict& options,
                       py::handle threads) {
  std::optional<Field> owned;
  const Field* phi = nullptr;
  std::string from;
  if (py::isinstance<Result>(source)) {
    const Result& r = py::cast<Result&>(source);
    phi = &r.result.phi;
    from = fmt::format("cmcsurf.Result: {}, grid {}", r.params.surface, r.params.grid);
  } else {
    owned = array_to_field(source, "phi");
    phi = &*owned;
    from = fmt::format("array of shape ({n}, {n}, {n})", fmt::arg("n", phi->n()));
  }
  VolumeMeshOptions o;
  std::string format;
  for (const auto& [k, v] : options) {
    const std::string key = py::cast<std::string>(k);
    if (v.is_none()) continue;
    if (key == "solid") o.solid = string_option(v, key);
    else if (key == "tile") o.tile = string_option(v, key);
    else if (key == "units") o.units = string_option(v, key);
    else if (key == "format") format = string_option(v, key);
    else if (key == "cut") o.cut = string_option(v, key);
    else if (key == "porosity") o.porosity = real_option(v, key);
    else if (key == "thickness") o.thickness = real_option(v, key);
    else if (key == "cell_size") o.cell_size = real_option(v, key);
    else if (key == "size") o.size = real_option(v, key);
    else if (key == "size_min") o.size_min = real_option(v, key);
    else if (key == "size_max") o.size_max = real_option(v, key);
    else if (key == "facet_distance") o.facet_distance = real_option(v, key);
    else throw py::type_error(fmt::format("unexpected keyword argument '{}'", key));
  }
  TetMeshFormat f;
  try {
    f = tet_mesh_format(format, out);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(fmt::format("format: {}", e.what()));
  }
  const VolumeMeshParams p = volume_mesh_params(o, phi->n());  // OptionError -> ValueError
  ThreadScope scope(threads);
  nlohmann::json report;
  {
    py::gil_scoped_release release;
    const VolumeMesh vm = build_volume_mesh(*phi, p);
    report = vm.report;
    report["source"] = from;
    write_tet_mesh_with_report(vm.mesh, f, out,
                               fmt::format("cmcsurf.volume_mesh: {} solid of {}",
                                           solid_kind_name(p.solid), from),
                               report);
  }
  return to_python(report);
}

// cmcsurf properties of a Result or an (N, N, N) field (pipeline/properties_stage.h): the
// dictionary of FILE.json. options: solid, phase, porosity, thickness, youngs_modulus_gpa,
// poisson_ratio, only (list), compare_nodal, grid_check, tolerance, cell_size, units, surface,
// flow_rate, flow_area, velocity, viscosity.
py::object properties(py::handle source, const py::dict& o, py::handle threads) {
  std::optional<Field> owned;
  const Field* phi = nullptr;
  PropertiesRequest r;
  if (py::isinstance<Result>(source)) {
    const Result& res = py::cast<Result&>(source);
    phi = &res.result.phi;
    r.surface = res.params.surface;
  } else {
    owned = array_to_field(source, "phi");
    phi = &*owned;
  }
  auto given = [&](const char* key) { return o.contains(key) && !o[key].is_none(); };
  if (given("cell_size")) r.cell_size = real_option(o["cell_size"], "cell_size");
  std::string shown;
  try {
    set_properties_solid(r, given("solid") ? string_option(o["solid"], "solid") : "network",
                         given("phase") ? integer_option(o["phase"], "phase", &shown) : 1,
                         given("porosity") ? real_option(o["porosity"], "porosity") : NAN,
                         given("thickness") ? real_option(o["thickness"], "thickness") : NAN);
    if (given("only"))
      set_properties_only(r, list_option(o["only"], "only", "a str or a sequence of str",
                                         [](py::handle e, const std::string& key) {
                                           return string_option(e, key);
                                         }));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  if (given("youngs_modulus_gpa"))
    r.youngs_modulus_gpa = real_option(o["youngs_modulus_gpa"], "material");
  if (given("poisson_ratio")) r.poisson_ratio = real_option(o["poisson_ratio"], "material");
  if (given("compare_nodal")) r.compare_nodal = bool_option(o["compare_nodal"], "compare_nodal");
  if (given("grid_check")) r.grid_check = bool_option(o["grid_check"], "grid_check");
  if (given("tolerance")) r.tolerance = real_option(o["tolerance"], "tolerance");
  if (given("units")) r.units = string_option(o["units"], "units");
  if (given("surface")) r.surface = string_option(o["surface"], "surface");
  if (given("flow_rate")) r.flow_rate_ml_min = real_option(o["flow_rate"], "flow_rate");
  if (given("flow_area")) r.flow_area = real_option(o["flow_area"], "flow_area");
  if (given("velocity")) r.velocity_mm_s = real_option(o["velocity"], "velocity");
  if (given("viscosity")) r.viscosity_mpa_s = real_option(o["viscosity"], "viscosity");
  if (const std::string why = check_properties_request(r); !why.empty())
    throw py::value_error(why);
  ThreadScope scope(threads);
  nlohmann::json j;
  {
    py::gil_scoped_release release;
    j = compute_properties(*phi, r);  // std::invalid_argument -> ValueError
  }
  if (!r.surface.empty()) j["surface"] = r.surface;
  return to_python(j);
}

// The --properties stage of run() and sweep() (properties=True, properties_solid=, ...; the
// options of `cmcsurf run --properties-*` without the prefix: solid, porosity, thickness,
// nodal, grid_check). check_properties_stage refuses bad ones before a solve;
// properties_stage adds the stage's keys to each Result's report (and to what save() writes)
// and returns sweep.csv's columns of the updated reports.
PropertiesStage stage_options(const py::dict& o) {
  PropertiesStage stage;
  stage.enabled = true;
  auto given = [&](const char* key) { return o.contains(key) && !o[key].is_none(); };
  if (given("solid")) stage.solid = string_option(o["solid"], "properties_solid");
  if (given("porosity"))  // P or a sequence (a ramp)
    for (py::handle p : py::list(o["porosity"]))
      stage.porosities.push_back(real_option(p, "properties_porosity"));
  if (given("thickness")) stage.thickness = real_option(o["thickness"], "properties_thickness");
  if (given("nodal")) stage.nodal = bool_option(o["nodal"], "properties_nodal");
  if (given("grid_check"))
    stage.grid_check = bool_option(o["grid_check"], "properties_grid_check");
  return stage;
}

void check_properties_stage(const py::dict& o, py::handle surface, py::handle grid) {
  std::string shown;
  try {
    stage_properties_request(stage_options(o), string_option(surface, "surface"),
                             int(integer_option(grid, "grid", &shown)));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

py::list properties_stage(const py::list& results, const py::dict& o, py::handle threads) {
  const PropertiesStage stage = stage_options(o);
  std::vector<Result*> members;
  for (py::handle h : results) members.push_back(&py::cast<Result&>(h));
  ThreadScope scope(threads);
  std::vector<nlohmann::json> reports;
  {
    py::gil_scoped_release release;
    for (Result* r : members) {
      const nlohmann::json keys = run_properties_keys(r->result.phi, r->params.surface, stage);
      r->extra.update(keys);
      r->report.update(keys);
      reports.push_back(r->report);
    }
  }
  for (Result* r : members) r->report_cache = py::object();
  return py::list(py::cast(sweep_columns(reports)));
}

// sweep(out=...) and sweep(resume=...): the library's sweep driver (driver/sweep_driver.h), so
// the folder is the one `cmcsurf sweep --out` writes and `--resume` continues. `folder`: dir,
// resume, force, and the output options float32, preview, report, plot, plot_diffuse,
// checkpoint_every (None: not given, so a resume takes sweep.json's value, a new sweep the
// command line's default); stage: the --properties stage's options or None; given: the
// keywords the caller gave (a resume compares those with sweep.json). Returns (results of the
// members run here, every member's report in sweep order, sweep.csv's columns).
py::tuple sweep_folder(py::handle surfaces_arg, py::handle fractions_arg, py::handle continuation,
                       const py::dict& options, const py::dict& folder, py::handle stage_arg,
                       const std::vector<std::string>& given_list, py::handle threads_arg,
                       py::object progress) {
  const std::filesystem::path dir = path_option(folder["dir"], "out");
  const bool resuming = bool_option(folder["resume"], "resume");
  const bool force = bool_option(folder["force"], "force");
  const std::set<std::string> given(given_list.begin(), given_list.end());
  SweepParams sp = sweep_params(surfaces_arg, fractions_arg, continuation, options);
  nlohmann::json saved = nlohmann::json::object();  // sweep.json's outputs
  if (resuming) {
    SweepResumeNames names;
    names.resume = "resume";
    names.surfaces = "surfaces";
    names.fractions = "volume_fractions";
    names.continuation = "continuation";
    names.surfaces_given = given.count("surfaces") > 0;
    names.fractions_given = given.count("volume_fractions") > 0;
    names.continuation_given = given.count("continuation") > 0;
    const SweepJson resumed = resumed_sweep(  // OptionError: ValueError
        dir, sp, names, [&](const nlohmann::json& parameters, const std::filesystem::path& f) {
          return resumed_run_params(
              sp.run, parameters, f, [&](const RunOption& o) { return given.count(o.key) > 0; },
              [](const RunOption& o) { return std::string(o.key); });
        });
    sp = resumed.sweep;
    saved = resumed.outputs;
  }
  // An output option: given, else sweep.json's (a resume), else the command line's default.
  auto output = [&](const char* keyword, const char* key, bool negated, bool fallback) {
    if (!folder[keyword].is_none()) return bool_option(folder[keyword], keyword);
    if (saved.contains(key) && saved[key].is_boolean()) return saved[key].get<bool>() != negated;
    return fallback;
  };
  PropertiesStage stage;
  std::string porosity;  // as sweep.json keeps --properties-porosity's text
  if (!stage_arg.is_none()) {
    stage = stage_options(py::cast<py::dict>(stage_arg));
  } else if (resuming && saved.value("properties", false)) {
    stage.enabled = true;
    stage.solid = saved.value("properties_solid", stage.solid);
    stage.nodal = saved.value("properties_nodal", false);
    stage.grid_check = saved.value("properties_grid_check", false);
    stage.thickness = saved.value("properties_thickness", stage.thickness);
    porosity = saved.value("properties_porosity", std::string());
    try {
      stage.porosities = parse_properties_porosities(porosity);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(fmt::format("resume: {}: {}", (dir / "sweep.json").string(),
                                        e.what()));
    }
  }
  if (!stage_arg.is_none() && !stage.porosities.empty())
    porosity = fmt::format("{}", fmt::join(stage.porosities, ","));
  if (stage.enabled) {
    try {
      stage_properties_request(stage, sp.surfaces.front(), sp.run.grid);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
  }
  refuse_if_too_large(sp.run);
  py::object threads = py::reinterpret_borrow<py::object>(threads_arg);
  if (resuming && given.count("threads") == 0 && saved.contains("threads") &&
      saved["threads"].is_number_integer())
    threads = py::int_(saved["threads"].get<int>());
  ThreadScope scope(threads);
  const auto world = Decomposition::world();
  SweepJob job;
  job.sweep = sp;
  job.dir = dir;
  job.resuming = resuming;
  job.force = force;
  job.plan = plan_groups(0, sp, *world);  // one group of this process
  job.member.threads = scope.count();
  job.member.float32 = output("float32", "float32", false, false);
  job.member.properties = stage;
  job.preview = output("preview", "no_preview", true, true);
  job.page = output("report", "no_report", true, true);
  job.figures = output("plot", "no_plot", true, true);
  job.diffuse = output("plot_diffuse", "plot_diffuse", false, false);
  // --checkpoint-every: given, else sweep.json's, else the command line's default.
  job.checkpoint_every = kDefaultCheckpointEvery;
  if (!folder["checkpoint_every"].is_none()) {
    job.checkpoint_every = real_option(folder["checkpoint_every"], "checkpoint_every");
    if (!(job.checkpoint_every >= 0.0 && job.checkpoint_every <= 1e9))
      throw py::value_error(fmt::format("checkpoint_every: got {}; accepted: 0 to 1e9 seconds",
                                        job.checkpoint_every));
  } else if (saved.contains("checkpoint_every") && saved["checkpoint_every"].is_number()) {
    job.checkpoint_every = saved["checkpoint_every"].get<double>();
  }
  job.outputs = sweep_outputs_json(job, porosity);
  job.resume_command =
      fmt::format("cmcsurf.sweep(resume={})", std::string(py::repr(py::str(dir.string()))));
  // One writer, and only into a folder that is ours (or new, or empty), before any work.
  FolderClaim claim;
  try {
    claim = claim_output_folder(
        dir, {.kind = "sweep", .option = resuming ? "resume" : "out", .force = force});
  } catch (const FolderRefused& e) {
    if (e.usage()) throw py::value_error(e.what());
    throw;
  }
  Interaction ia(std::move(progress));
  std::vector<std::shared_ptr<Result>> results;
  std::map<int, nlohmann::json> reports;  // by member index: run here or kept
  std::string errors;
  std::vector<std::string> notices;
  SweepHooks hooks;
  hooks.notice = [&](const std::string& text) { notices.push_back(text); };
  hooks.warning = [&](const std::string& text) { notices.push_back(text); };
  hooks.error = [&](const std::string& text) { errors += text; };
  hooks.starting = [&](const SweepMember& m) { ia.set_member(m.name); };
  hooks.kept = [&](const SweepMember& m, const nlohmann::json& report) {
    reports[m.index] = report;
  };
  hooks.finished = [&](const SweepMember& m, const nlohmann::json& report) {
    reports[m.index] = report;
  };
  hooks.result = [&](const SweepMember& m, const RunResult& r, const CmcQuality& q,
                     const nlohmann::json& report) {
    results.push_back(std::make_shared<Result>(m.params, r, scope.count(),
                                               nlohmann::json{{"volume_fraction_target", m.alpha},
                                                              {"member", m.name},
                                                              {"started_from", m.started_from}},
                                               q, report));
  };
  hooks.step = [&](const StepRecord& r) { ia.step(r); };
  hooks.stop_requested = [&] { return ia.stop_requested(); };
  hooks.stop_code = [] { return 130; };  // as a SIGINT's
  hooks.signal_name = [&] { return ia.stop_name(); };
  SweepOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = drive_sweep(job, hooks);
  }
  for (const std::string& text : notices)
    if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
  ia.raise_pending();  // KeyboardInterrupt, or what progress raised: the member's checkpoint kept
  // The command line's message, without its "error: " and newline.
  std::string message = errors;
  if (message.rfind("error: ", 0) == 0) message.erase(0, 7);
  while (!message.empty() && message.back() == '\n') message.pop_back();
  if (outcome.exit_code == 2) throw py::value_error(message);
  if (outcome.exit_code != 0) throw std::runtime_error(message);
  std::vector<nlohmann::json> all;
  py::list dicts;
  for (const auto& [index, report] : reports) {
    all.push_back(report);
    dicts.append(to_python(report));
  }
  return py::make_tuple(results, dicts, sweep_columns(all));
}

// cmcsurf scattering of a Result or an (N, N, N) field (science/scattering.h): the dictionary
// of scattering.json, with the columns of reflections.csv ("reflections") and saxs.csv
// ("saxs") as NumPy arrays.
py::object scattering(py::handle source, const py::dict& o, py::handle threads) {
  std::optional<Field> owned;
  const Field* phi = nullptr;
  if (py::isinstance<Result>(source)) {
    phi = &py::cast<Result&>(source).result.phi;
  } else {
    owned = array_to_field(source, "phi");
    phi = &*owned;
  }
  auto given = [&](const char* key) { return o.contains(key) && !o[key].is_none(); };
  ScatteringParams sp;
  std::string shown;
  try {
    if (given("density")) sp.density = parse_density_model(string_option(o["density"], "density"));
    if (given("smax"))
      sp.smax = int(std::clamp<long long>(integer_option(o["smax"], "smax", &shown), -1, 1 << 30));
    if (sp.smax < 0) throw std::invalid_argument("--smax: accepted: S >= 0 (0: automatic)");
    if (given("lattice")) sp.powder.lattice = real_option(o["lattice"], "lattice");
    if (given("debye_waller"))
      sp.powder.debye_waller = real_option(o["debye_waller"], "debye_waller");
    if (given("peak_width")) sp.powder.peak_width = real_option(o["peak_width"], "peak_width");
    if (given("peak_shape")) {
      const std::string shape = string_option(o["peak_shape"], "peak_shape");
      if (shape != "gaussian" && shape != "lorentzian")
        throw std::invalid_argument(
            fmt::format("--peak-shape: got '{}'; accepted: gaussian, lorentzian", shape));
      sp.powder.lorentzian = shape == "lorentzian";
    }
    if (given("absent_tol")) sp.absent_tol = real_option(o["absent_tol"], "absent_tol");
    if (given("index_tol")) sp.index_tol = real_option(o["index_tol"], "index_tol");
    if (!(sp.powder.lattice > 0.0 && std::isfinite(sp.powder.lattice)))
      throw std::invalid_argument(
          fmt::format("--lattice: got {}; accepted: > 0", sp.powder.lattice));
    if (!(sp.powder.debye_waller >= 0.0 && std::isfinite(sp.powder.debye_waller)))
      throw std::invalid_argument("--debye-waller: accepted: >= 0");
    if (!(sp.powder.peak_width >= 0.0 && std::isfinite(sp.powder.peak_width)))
      throw std::invalid_argument("--peak-width: accepted: >= 0");
    if (!(sp.absent_tol > 0.0 && sp.absent_tol < 1.0))
      throw std::invalid_argument("--absent-tol: accepted: 0 < T < 1");
    if (!(sp.index_tol > 0.0 && sp.index_tol < 1.0))
      throw std::invalid_argument("--index-tol: accepted: 0 < T < 1");
    if (given("peaks"))
      for (py::handle q : o["peaks"]) {
        const double v = real_option(q, "peaks");
        if (!(v > 0.0 && std::isfinite(v)))
          throw std::invalid_argument(fmt::format("--peaks: {} is not a peak position; accepted: "
                                                  "q > 0 in 1/nm", v));
        sp.peaks.push_back(v);
      }
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  ThreadScope scope(threads);
  ScatteringResult result;
  nlohmann::json j;
  {
    py::gil_scoped_release release;
    result = scattering_analysis(*phi, sp);  // std::invalid_argument -> ValueError
    j = scattering_json(result, sp);
  }
  py::dict d = to_python(j);
  const std::size_t m = result.classes.size();
  py::array_t<std::int64_t> h(m), k(m), l(m), s(m), mult(m);
  py::array_t<double> intensity(m), amplitude(m), phase(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Reflection& r = result.classes[i];
    h.mutable_at(i) = r.h, k.mutable_at(i) = r.k, l.mutable_at(i) = r.l, s.mutable_at(i) = r.s;
    mult.mutable_at(i) = r.multiplicity;
    intensity.mutable_at(i) = r.intensity, amplitude.mutable_at(i) = r.amplitude;
    phase.mutable_at(i) = r.phase;
  }
  py::dict reflections;
  reflections["h"] = h, reflections["k"] = k, reflections["l"] = l, reflections["s"] = s;
  reflections["multiplicity"] = mult, reflections["intensity"] = intensity;
  reflections["amplitude"] = amplitude, reflections["phase"] = phase;
  d["reflections"] = reflections;
  py::dict saxs;
  saxs["q"] = py::array_t<double>(result.powder.q.size(), result.powder.q.data());
  saxs["intensity"] =
      py::array_t<double>(result.powder.intensity.size(), result.powder.intensity.data());
  d["saxs"] = saxs;
  return d;
}

py::list surfaces() {
  py::list out;
  for (const SurfaceInfo& s : builtin_surfaces()) {
    py::dict d;
    d["name"] = s.name;
    d["nodal"] = s.nodal;
    d["balanced"] = s.nodal ? py::object(py::bool_(s.balanced)) : py::object(py::none());
    d["description"] = s.description;
    out.append(d);
  }
  return out;
}

// ---- docstrings (help(cmcsurf.Result), help(cmcsurf.Mesh)) --------------------------------

constexpr const char* kResultDoc = R"(A run's result: the field, report and history of one solve.

Made by cmcsurf.run, relax and sweep; immutable. Its numbers are those of the command line's
run folder at equal parameters and thread count (report.json, history.csv, field.vti).)";

constexpr const char* kResultPhiDoc = R"(The final field phi: float64 (N, N, N), read-only.

Indexed [i, j, k] = the cell centred at ((i + 1/2) / N, (j + 1/2) / N, (k + 1/2) / N), i.e. the
(x, y, z) axes of numpy.meshgrid(..., indexing="ij"); phase 1 is phi > 1/2.)";

constexpr const char* kResultReportDoc = R"(report.json of the run, as a dict.

Every key of the command line's report.json (same values, bit for bit at equal thread
count), except preview_seconds, page_seconds and write_seconds: the preview, the page's
meshes and the writes run in save(), whose report.json has them.
A sweep member's report adds member, started_from and volume_fraction_target, as the
member's report.json in a `cmcsurf sweep` folder.)";

// Result.history's doc: the columns of history.csv's table (schema/report_schema.h).
const char* result_history_doc() {
  static const std::string doc = [] {
    std::string out = "history.csv as a dict of NumPy columns, one row per time step:\n";
    for (const HistoryColumnInfo& c : history_column_table())
      out += fmt::format("\n{} ({}): {}", c.name,
                         c.type == HistoryType::kInt    ? "int64"
                         : c.type == HistoryType::kText ? "str"
                                                        : "float64",
                         c.help);
    return out;
  }();
  return doc.c_str();
}

// The report schema (schema/report_schema.h) as Python data: report keys, history columns,
// stages, sweep.csv's leading columns, the families table.
py::object report_schema() {
  return to_python(nlohmann::json::parse(report_schema_json()));
}

constexpr const char* kResultSaveDoc =
    R"(save(dir, float32=False, preview=True, report=True, force=False) -> pathlib.Path

Writes the run folder exactly as `cmcsurf run --out dir` does: history.csv,
curvature_histogram.csv, curvature_distribution.csv, field.vti (float32=True: single
precision, as --float32), preview.png, report.json (last; with preview_seconds) and
report.html. preview=False is --no-preview (no preview.png), report=False is --no-report
(no report.html; `cmcsurf report dir` writes it later). An earlier run's outputs in dir are
removed first. dir must be new,
empty or a cmcsurf folder (force=True writes into another non-empty folder, as --force), and
no other process may be writing it (ValueError / RuntimeError otherwise, before anything is
written). Returns dir as a pathlib.Path.)";

constexpr const char* kMeshDoc = R"(A watertight triangle mesh of a field, made by cmcsurf.mesh.

Coordinates are in output units (cell_size per unit cell); immutable.)";

constexpr const char* kMeshVerticesDoc = R"(Vertex coordinates: float64 (n, 3), read-only.

(x, y, z) along the field's axes i, j, k, times cell_size, over the tiled box.)";

constexpr const char* kMeshFacesDoc = R"(Triangles: int64 (m, 3), read-only.

Indices into vertices, counter-clockwise seen from outside (the solid's outward normal).)";

constexpr const char* kMeshReportDoc = R"(The mesh's report, as a dict: FILE.json of `cmcsurf mesh`.

Counts (triangles, vertices), area, volume (solids), Euler characteristic, the checks
(closed, manifold, ...) and topology; save() adds file, format, file_bytes, write_seconds,
version and source to the FILE.json it writes.)";

constexpr const char* kMeshSaveDoc = R"(save(path, format="") -> pathlib.Path

Writes the mesh (stl, ply, obj or 3mf; from path's extension unless format is given) and
path.json, as `cmcsurf mesh --out path` does; path.json's source names the Result or array the
mesh came from. Returns path as a pathlib.Path.)";

}  // namespace

void register_analysis(py::module_& m);  // python/src/analysis.cpp

PYBIND11_MODULE(_cmcsurf, m) {
  m.doc() = "The compiled core of cmcsurf; use the functions of the cmcsurf package.";
  // OpenMP starts OMP_NUM_THREADS threads at the first parallel region (100000: a crash), and
  // a call's threads= does not reach Result.save or initial_field: refused as the CLI does.
  if (const std::string why = check_omp_num_threads(std::getenv("OMP_NUM_THREADS"));
      !why.empty())
    throw py::import_error("OMP_NUM_THREADS: " + why);
  py::register_exception<SolverDiverged>(m, "SolverDiverged", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("version", [] { return std::string(CMCSURF_VERSION); });
  m.def("surfaces", &surfaces);
  m.def("default_options", [] { return to_python(params_json(RunParams{})); });
  m.def("run_options", &run_option_schema);
  m.def("report_schema", &report_schema);
  m.def("run", &run, py::arg("options"), py::arg("threads"), py::arg("progress"));
  m.def("relax", &relax, py::arg("phi"), py::arg("volume_fraction"), py::arg("algorithm"),
        py::arg("options"), py::arg("threads"), py::arg("progress"));
  m.def("initial_field", &initial_field, py::arg("options"));
  m.def("measure", &measure, py::arg("phi"), py::arg("options"), py::arg("threads"));
  m.def("sweep", &sweep, py::arg("surfaces"), py::arg("fractions"), py::arg("continuation"),
        py::arg("options"), py::arg("threads"), py::arg("progress"));
  m.def("default_checkpoint_every", [] { return kDefaultCheckpointEvery; });
  m.def("sweep_folder", &sweep_folder, py::arg("surfaces"), py::arg("fractions"),
        py::arg("continuation"), py::arg("options"), py::arg("folder"), py::arg("stage"),
        py::arg("given"), py::arg("threads"), py::arg("progress"));
  m.def("mesh", &mesh, py::arg("source"), py::arg("options"), py::arg("threads"));
  m.def("properties", &properties, py::arg("source"), py::arg("options"), py::arg("threads"));
  m.def("volume_mesh", &volume_mesh, py::arg("source"), py::arg("out"), py::arg("options"),
        py::arg("threads"));
  m.def("check_properties_stage", &check_properties_stage, py::arg("options"),
        py::arg("surface"), py::arg("grid"));
  m.def("properties_stage", &properties_stage, py::arg("results"), py::arg("options"),
        py::arg("threads"));
  m.def("scattering", &scattering, py::arg("source"), py::arg("options"), py::arg("threads"));
  register_scaffold(m);
  register_analysis(m);  // python/src/analysis.cpp

  // The methods' docstrings begin with their own signature, in the package's types.
  py::options options;
  options.disable_function_signatures();
  py::class_<Result, std::shared_ptr<Result>>(m, "Result", kResultDoc)
      .def_property_readonly("phi", &Result::phi, kResultPhiDoc)
      .def_property_readonly("report", &Result::report_dict, kResultReportDoc)
      .def_property_readonly("history", &Result::history, result_history_doc())
      .def("save", &Result::save, py::arg("dir"), py::arg("float32") = false,
           py::arg("preview") = true, py::arg("report") = true, py::arg("force") = false,
           kResultSaveDoc);
  py::class_<Mesh, std::shared_ptr<Mesh>>(m, "Mesh", kMeshDoc)
      .def_property_readonly("vertices", &Mesh::vertices, kMeshVerticesDoc)
      .def_property_readonly("faces", &Mesh::faces, kMeshFacesDoc)
      .def_property_readonly("report", &Mesh::report_dict, kMeshReportDoc)
      .def("save", &Mesh::save, py::arg("path"), py::arg("format") = "", kMeshSaveDoc);
}

}  // namespace cmcsurf::python
