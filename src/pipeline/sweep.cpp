#include "pipeline/sweep.h"

#include <fmt/format.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include "common/wall_clock.h"
#include "io/run_report.h"
#include "measure/measures.h"
#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"
#include "model/option_checks.h"
#include "model/run_options.h"
#include "surfaces/nodal_level.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

constexpr int kMaxMembers = 1000;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

double parse_number(const std::string& text, const std::string& spec) {
  const std::string t = trim(text);
  char* end = nullptr;
  const double v = t.empty() ? NAN : std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v))
    throw std::invalid_argument(fmt::format(
        "'{}' in '{}' is not a number; accepted: start:stop:step (e.g. 0.25:0.75:0.05) or a "
        "list (e.g. 0.3,0.5,0.7)",
        text, spec));
  return v;
}

void check_fraction(double v, const std::string& spec) {
  if (!(v > 0.0 && v < 1.0))
    throw std::invalid_argument(
        fmt::format("volume fraction {} in '{}' is outside (0, 1); accepted: 0 < A < 1", v, spec));
}

// Splits at commas outside parentheses.
std::vector<std::string> split_top_level(const std::string& s) {
  std::vector<std::string> parts;
  std::string cur;
  int depth = 0;
  for (char ch : s) {
    if (ch == '(') ++depth;
    if (ch == ')') --depth;
    if (ch == ',' && depth <= 0) {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  parts.push_back(cur);
  return parts;
}

}  // namespace

std::vector<double> parse_volume_fractions(const std::string& spec) {
  std::vector<double> out;
  if (spec.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::size_t pos = 0;
    for (std::size_t c; (c = spec.find(':', pos)) != std::string::npos; pos = c + 1)
      parts.push_back(spec.substr(pos, c - pos));
    parts.push_back(spec.substr(pos));
    if (parts.size() != 3)
      throw std::invalid_argument(
          fmt::format("'{}' is not start:stop:step (e.g. 0.25:0.75:0.05)", spec));
    const double start = parse_number(parts[0], spec), stop = parse_number(parts[1], spec),
                 step = parse_number(parts[2], spec);
    check_fraction(start, spec);
    check_fraction(stop, spec);
    if (start > stop)
      throw std::invalid_argument(
          fmt::format("start {} > stop {} in '{}'; accepted: start <= stop", start, stop, spec));
    if (!(step > 0.0))
      throw std::invalid_argument(
          fmt::format("step {} in '{}'; accepted: step > 0", step, spec));
    const double count = std::floor((stop - start) / step + 1e-9) + 1.0;
    if (count > kMaxMembers)
      throw std::invalid_argument(fmt::format("'{}' gives {} fractions; accepted: at most {}",
                                              spec, count, kMaxMembers));
    for (int i = 0; i < int(count); ++i)  // rounded so that 0.25 + 2 * 0.05 prints as 0.35
      out.push_back(std::round((start + i * step) * 1e12) / 1e12);
    return out;
  }
  for (const std::string& part : split_top_level(spec)) {
    const double v = parse_number(part, spec);
    check_fraction(v, spec);
    out.push_back(v);
  }
  if (int(out.size()) > kMaxMembers)
    throw std::invalid_argument(fmt::format("at most {} volume fractions", kMaxMembers));
  return out;
}

std::vector<std::string> parse_surface_list(const std::string& spec) {
  std::vector<std::string> out;
  for (const std::string& part : split_top_level(spec)) {
    const std::string name = trim(part);
    if (name.empty())
      throw std::invalid_argument(fmt::format("empty surface name in '{}'", spec));
    validate_surface(name);  // throws, naming the accepted surfaces
    if (!is_nodal_surface(name))
      throw std::invalid_argument(fmt::format(
          "'{}' has no nodal formula, so no volume fraction to sweep; accepted: P, D, G and the "
          "other nodal surfaces of `cmcsurf surfaces`, or expr:<formula>",
          name));
    out.push_back(name);
  }
  return out;
}

void check_sweep_params(const SweepParams& params) {
  if (params.surfaces.empty()) throw std::invalid_argument("no surfaces");
  for (const std::string& name : params.surfaces) {
    validate_surface(name);
    if (!is_nodal_surface(name))
      throw std::invalid_argument(fmt::format("'{}' has no nodal formula to sweep", name));
  }
  if (params.fractions.empty() || int(params.fractions.size()) > kMaxMembers)
    throw std::invalid_argument(fmt::format("{} volume fractions; accepted: 1 to {}",
                                            params.fractions.size(), kMaxMembers));
  for (double v : params.fractions) {
    check_fraction(v, "volume_fractions");
    if (const std::string why = check_fraction_on_grid(v, params.run.grid);
        params.run.grid >= 8 && !why.empty())
      throw std::invalid_argument(why);
  }
  // Each member has a folder of its own: two with one name would write into one folder.
  std::vector<std::string> names;
  for (std::size_t s = 0; s < params.surfaces.size(); ++s)
    for (double alpha : params.fractions) {
      const std::string name = member_name(params.surfaces[s], int(s), alpha);
      if (std::find(names.begin(), names.end(), name) != names.end())
        throw std::invalid_argument(fmt::format(
            "two members named '{}' (surface {}, volume fraction {}): each surface and each "
            "volume fraction may be given once",
            name, params.surfaces[s], alpha));
      names.push_back(name);
    }
  try {
    check_run_params(params.run, false);
  } catch (const OptionError& e) {
    throw std::invalid_argument(e.what());
  }
}

std::string member_name(const std::string& surface, int surface_index, double alpha) {
  const std::string base =
      surface.rfind("expr:", 0) == 0 ? fmt::format("expr{}", surface_index) : surface;
  std::string a = fmt::format("{:.2f}", alpha);
  if (std::abs(std::stod(a) - alpha) > 1e-12) a = fmt::format("{:.6g}", alpha);
  return base + "_" + a;
}

void check_member_name(const std::string& name, const std::string& source) {
  static constexpr const char* kAllowed =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.+-";
  const bool plain = !name.empty() && name.size() <= 255 && name != "." && name != ".." &&
                     name.find_first_not_of(kAllowed) == std::string::npos;
  if (!plain) {
    std::string shown;  // control characters and NUL made visible
    for (const char c : name)
      shown += static_cast<unsigned char>(c) < 0x20 ? fmt::format("\\x{:02x}", int(c))
                                                    : std::string(1, c);
    throw std::invalid_argument(fmt::format(
        "'{}': member name '{}' is not a plain folder name; a sweep's members are folders "
        "directly inside it, named like G_0.30 (letters, digits and _.+- only)",
        source, shown));
  }
}

std::string checked_member_name(const std::string& surface, int surface_index, double alpha,
                                const std::string& source) {
  std::string name = member_name(surface, surface_index, alpha);
  check_member_name(name, source);
  return name;
}

SweepJson parse_sweep_json(const nlohmann::json& j) {
  if (!j.is_object()) throw std::invalid_argument("the file holds no JSON object");
  auto convert = [](const nlohmann::json& v, auto& value, const std::string& what) {
    try {
      value = json_value<std::remove_cvref_t<decltype(value)>>(v, what);
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument(e.what());
    }
  };
  // Key of object o (`where` its path in messages); missing is an error unless optional.
  auto read = [&](const nlohmann::json& o, const std::string& where, const char* key,
                  auto& value, bool optional = false) {
    if (!o.contains(key)) {
      if (optional) return false;
      throw std::invalid_argument(fmt::format("'{}{}' is missing", where, key));
    }
    convert(o.at(key), value, fmt::format("'{}{}'", where, key));
    return true;
  };
  auto list = [](const nlohmann::json& o, const char* key) -> const nlohmann::json& {
    if (!o.contains(key) || !o.at(key).is_array())
      throw std::invalid_argument(fmt::format(
          "'{}' is {}; accepted: a list", key,
          o.contains(key) ? o.at(key).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
                          : "missing"));
    if (o.at(key).size() > std::size_t(kMaxMembers))
      throw std::invalid_argument(fmt::format("'{}' holds {} entries; accepted: at most {}", key,
                                              o.at(key).size(), kMaxMembers));
    return o.at(key);
  };
  SweepJson out;
  SweepParams& sp = out.sweep;
  for (const nlohmann::json& s : list(j, "surfaces")) {
    const std::string what = fmt::format("'surfaces[{}]'", sp.surfaces.size());
    convert(s, sp.surfaces.emplace_back(), what);
  }
  for (const nlohmann::json& v : list(j, "volume_fractions")) {
    const std::string what = fmt::format("'volume_fractions[{}]'", sp.fractions.size());
    convert(v, sp.fractions.emplace_back(), what);
  }
  read(j, "", "continuation", sp.continuation);
  if (!j.contains("parameters"))
    throw std::invalid_argument("'parameters' is missing");
  try {
    sp.run = params_from_json(j.at("parameters"));
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(fmt::format("'parameters': {}", e.what()));
  }
  check_sweep_params(sp);  // surfaces, fractions, the run's ranges
  for (std::size_t s = 0; s < sp.surfaces.size(); ++s)
    for (double alpha : sp.fractions)
      checked_member_name(sp.surfaces[s], int(s), alpha, "surfaces");
  // Informational keys: in range when present.
  const std::size_t total = sp.surfaces.size() * sp.fractions.size();
  std::size_t members = 0;
  if (read(j, "", "members", members, true) && members > total)
    throw std::invalid_argument(fmt::format("'members': got {}; accepted: 0 to the {} members of "
                                            "the sweep", members, total));
  int threads = 0;
  if (read(j, "", "threads", threads, true))
    if (const std::string why = check_threads(threads); !why.empty())
      throw std::invalid_argument(fmt::format("'threads': {}", why));
  double wall = 0.0;
  if (read(j, "", "wall_seconds", wall, true) && !(wall >= 0.0 && wall <= 1e12))
    throw std::invalid_argument(fmt::format("'wall_seconds': got {}; accepted: 0 to 1e12", wall));
  if (j.contains("mpi")) {
    const nlohmann::json& mpi = j.at("mpi");
    if (!mpi.is_object()) throw std::invalid_argument("'mpi' is not an object");
    for (const char* key : {"ranks", "groups", "ranks_per_group"}) {
      int v = 1;
      if (read(mpi, "mpi.", key, v, true) && v < 1)
        throw std::invalid_argument(fmt::format("'mpi.{}': got {}; accepted: >= 1", key, v));
    }
  }
  // The output options a resume may restore; python and plot_script only checked, not returned.
  if (!j.contains("outputs")) return out;
  const nlohmann::json& o = j.at("outputs");
  if (!o.is_object()) throw std::invalid_argument("'outputs' is not an object");
  if (read(o, "outputs.", "threads", threads, true)) {
    if (const std::string why = check_threads(threads); !why.empty())
      throw std::invalid_argument(fmt::format("'outputs.threads': {}", why));
    out.outputs["threads"] = threads;
  }
  for (const char* key : {"float32", "no_preview", "no_report", "no_plot", "plot_diffuse",
                          "properties",
                          "properties_nodal", "properties_grid_check"}) {
    bool flag = false;
    if (read(o, "outputs.", key, flag, true)) out.outputs[key] = flag;
  }
  // The --properties stage's solid; its ranges are checked where the command line's are.
  for (const char* key : {"properties_solid", "properties_porosity"}) {
    std::string text;
    if (read(o, "outputs.", key, text, true)) out.outputs[key] = text;
  }
  double thickness = 0.0;
  if (read(o, "outputs.", "properties_thickness", thickness, true))
    out.outputs["properties_thickness"] = thickness;
  double every = 0.0;
  if (read(o, "outputs.", "checkpoint_every", every, true)) {
    if (!(every >= 0.0 && every <= 1e9))
      throw std::invalid_argument(
          fmt::format("'outputs.checkpoint_every': got {}; accepted: 0 to 1e9 seconds", every));
    out.outputs["checkpoint_every"] = every;
  }
  for (const char* key : {"python", "plot_script"}) {
    std::string ignored;
    read(o, "outputs.", key, ignored, true);
  }
  return out;
}

RunResult run_from_neighbour(const Field& neighbour, double neighbour_alpha,
                             const RunParams& params, const RunContext& context,
                             FinalFieldCache* cache) {
  const double alpha = params.volume_fraction;
  Field phi0(params.grid, 2, context.decomposition);
  copy_interior(neighbour, phi0);
  if (params.constrain == Constraint::kMass) {
    shift_mean(phi0, alpha);  // step 5
  } else {
    // A sharp interface between the bulk phases moves by the added mass: shift by the change
    // of alpha, then let the volume constraint's secant iteration finish the job.
    add_constant(phi0, alpha - neighbour_alpha);
    phi0.exchange_halo();
  }
  return relax_to_volume_fraction(phi0, params, context, cache);
}

CmcQuality measure_cmc_quality(const Field& relaxed, const RunParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  Field psi = Field::like(relaxed, 2);
  tanh_profile_inverse(relaxed, psi);
  CmcQuality q = measure_cmc_quality_psi(
      psi, is_nodal_surface(params.surface) ? sharp_volume_fraction(relaxed) : 0.0, params);
  q.seconds = seconds_since(t0);
  return q;
}

CmcQuality measure_cmc_quality_psi(const Field& psi, double volume_fraction,
                                   const RunParams& params,
                                   const std::vector<CurvatureSample>* known_samples) {
  const auto t0 = std::chrono::steady_clock::now();
  CmcQuality q;
  std::vector<CurvatureSample> computed;
  if (!known_samples) level_set_surface(psi, &computed);
  const std::vector<CurvatureSample>& relaxed_samples = known_samples ? *known_samples : computed;
  if (is_nodal_surface(params.surface)) {
    // The nodal surface with the relaxed surface's sharp volume fraction.
    const double v = volume_fraction;
    const NodalLevelSet nodal =
        nodal_level_set(params.surface, v > 0.0 && v < 1.0 ? v : params.volume_fraction,
                        params.grid, 1e-7, psi.shared_decomposition());
    std::vector<CurvatureSample> nodal_samples;
    const LevelSetSurface s = level_set_surface(nodal_level_function(nodal), &nodal_samples);
    fill_distributions(q, relaxed_samples, &nodal_samples, psi.decomposition());
    q.nodal_level = nodal.level;
    q.nodal_volume_fraction = nodal.volume_fraction;
    q.nodal_area = s.area;
    q.nodal_mean_curvature = s.mean_curvature;
    Field tanh_phi = nodal_tanh_profile(nodal, params.epsilon);
    q.nodal_area_diffuse = area(tanh_phi, params.epsilon);
    q.nodal_mean_curvature_diffuse = mean_curvature(tanh_phi);
  } else {
    fill_distributions(q, relaxed_samples, nullptr, psi.decomposition());
  }
  q.seconds = seconds_since(t0);
  return q;
}

void run_sweep(const SweepParams& params, const std::function<void(const SweepMember&)>& starting,
               const MemberFn& done, const RunContext& context, const PlanFn& plan) {
  const int count = int(params.surfaces.size() * params.fractions.size());
  int index = 0;
  for (std::size_t s = 0; s < params.surfaces.size(); ++s) {
    Field previous;  // this process's block under a decomposition
    std::string previous_name;
    double previous_alpha = 0.0;
    bool ran_here = false, elsewhere = false;  // members of this family here and elsewhere
    auto keep = [&](const Field& phi, double alpha, const std::string& name) {
      previous = Field(params.run.grid, 2, context.decomposition);
      if (phi.whole() && !previous.whole())
        take_block(phi, previous);  // a kept member's field.vti
      else
        copy_interior(phi, previous);
      previous_name = name;
      previous_alpha = alpha;
    };
    for (double alpha : params.fractions) {
      SweepMember m;
      m.index = index++;
      m.count = count;
      m.surface = params.surfaces[s];
      m.alpha = alpha;
      m.name = member_name(m.surface, int(s), alpha);
      m.params = params.run;
      m.params.surface = m.surface;
      m.params.volume_fraction = alpha;
      const bool continued = params.continuation && !previous_name.empty();
      m.started_from = continued ? previous_name : "nodal";
      MemberStart start = plan ? plan(m) : MemberStart{};
      const bool here = start.kind != MemberStart::Kind::kElsewhere;
      (here ? ran_here : elsewhere) = true;
      if (params.continuation && ran_here && elsewhere)
        throw std::logic_error(fmt::format(
            "run_sweep: the family of {} is split between groups; continuation needs it whole",
            m.surface));
      if (!here) continue;
      if (start.kind == MemberStart::Kind::kSkip) {  // done before
        if (params.continuation) keep(start.field, alpha, m.name);
        continue;
      }
      if (starting) starting(m);
      RunResult r;
      FinalFieldCache cache;
      if (start.kind == MemberStart::Kind::kResume) {  // its checkpoint holds its start
        RunContext resumed = context;
        resumed.resume = start.checkpoint;
        r = continued ? relax_to_volume_fraction(Field(), m.params, resumed, &cache)
                      : run_cmc(m.params, resumed, &cache);
      } else {
        r = continued ? run_from_neighbour(previous, previous_alpha, m.params, context, &cache)
                      : run_cmc(m.params, context, &cache);
      }
      if (params.continuation) keep(r.phi, alpha, m.name);
      if (done) done(m, std::move(r), std::move(cache));
    }
  }
}

}  // namespace cmcsurf
