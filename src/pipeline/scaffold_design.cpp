#include "pipeline/scaffold_design.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "common/wall_clock.h"
#include "io/mesh_output.h"
#include "properties/cell_properties.h"

namespace cmcsurf {

namespace {

double mean_of_three(const nlohmann::json& v) {
  if (v[0].is_array())  // a tensor: its mean diagonal
    return (v[0][0].get<double>() + v[1][1].get<double>() + v[2][2].get<double>()) / 3.0;
  return (v[0].get<double>() + v[1].get<double>() + v[2].get<double>()) / 3.0;
}

const char* quantity_name(TargetQuantity q) {
  return q == TargetQuantity::kModulus ? "modulus" : "permeability";
}

const char* quantity_unit(TargetQuantity q) {
  return q == TargetQuantity::kModulus ? "GPa" : "m^2";
}

double target_of(const DesignTargets& t, TargetQuantity q) {
  return q == TargetQuantity::kModulus ? t.modulus_gpa : t.permeability_m2;
}

// Log-log guesses of the first step: a bending-dominated network's modulus goes as (1 - p)^2
// (Gibson-Ashby, prefactor about 1/2 for TPMS networks), a sheet's closer to (1 - p)^1.5; a
// permeability as Kozeny-Carman's p^3 / (1 - p)^2.
double modulus_exponent(SolidKind solid) { return solid == SolidKind::kSheet ? 1.5 : 2.0; }

}  // namespace

TargetValue parse_target_value(const std::string& text, const std::string& option) {
  TargetValue v;
  if (text.empty()) return v;
  const auto bad = [&] {
    return std::invalid_argument(fmt::format(
        "{}: got '{}'; accepted: a positive number V, or A:B (a ramp along --axis)", option,
        text));
  };
  auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double x = NAN;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (part.empty() || used != part.size() || !(x > 0.0) || !std::isfinite(x)) throw bad();
    return x;
  };
  const std::size_t colon = text.find(':');
  v.from = number(text.substr(0, colon));
  v.to = colon == std::string::npos ? v.from : number(text.substr(colon + 1));
  if (colon != std::string::npos && v.from == v.to) throw bad();
  return v;
}

const char* target_option(TargetQuantity q) {
  return q == TargetQuantity::kModulus ? "--target-modulus" : "--target-permeability";
}

std::pair<double, double> design_porosity_range(SolidKind solid) {
  return solid == SolidKind::kSheet ? std::pair{kSheetPorosityMin, kSheetPorosityMax}
                                    : std::pair{kNetworkPorosityMin, kNetworkPorosityMax};
}

DesignPlan plan_design(const DesignProblem& p) {
  const DesignTargets& t = p.targets;
  const bool modulus = !std::isnan(t.modulus_gpa), permeability = !std::isnan(t.permeability_m2),
             pore = !std::isnan(t.pore_size);
  for (const auto& [v, name] : {std::pair{t.modulus_gpa, "--target-modulus"},
                                {t.permeability_m2, "--target-permeability"},
                                {t.pore_size, "--pore-size"}, {t.min_wall, "--min-wall"}})
    if (!std::isnan(v) && !(v > 0.0 && std::isfinite(v)))
      throw std::invalid_argument(fmt::format("{}: got {}; accepted: > 0", name, v));
  if (modulus && p.porosity_given)
    throw std::invalid_argument("--target-modulus: it solves the porosity; give it or "
                                "--porosity, not both");
  DesignPlan plan;
  if (!p.porosity_given) {
    if (!modulus && !permeability)
      throw std::invalid_argument("--porosity: required (or --target-modulus or "
                                  "--target-permeability to solve it)");
    plan.solve_porosity = true;
    plan.porosity_by = modulus ? TargetQuantity::kModulus : TargetQuantity::kPermeability;
  }
  plan.cell_size_by_permeability =
      permeability && !(plan.solve_porosity && plan.porosity_by == TargetQuantity::kPermeability);
  plan.cell_size_by_pore_size = pore;
  if (plan.cell_size_by_permeability && plan.cell_size_by_pore_size)
    throw std::invalid_argument(
        "--pore-size and --target-permeability: each fixes the cell size once the porosity is "
        "set (permeability scales with its square, pore size with it); give one");
  if ((plan.cell_size_by_permeability || plan.cell_size_by_pore_size) && p.cell_size_given)
    throw std::invalid_argument(fmt::format(
        "--cell-size: {} solves it; give one of them",
        plan.cell_size_by_pore_size ? "--pore-size" : "--target-permeability (with the "
                                                      "porosity given or solved)"));
  if (modulus && std::isnan(p.material.youngs_modulus_gpa))
    throw std::invalid_argument(
        "--target-modulus: needs --material E_GPa[,nu] (the solid's Young's modulus)");
  if (permeability && std::isnan(metres_per_unit(p.design.units)))
    throw std::invalid_argument(fmt::format(
        "--target-permeability: needs a physical --units (um, mm, cm, m, in); got {}",
        p.design.units));
  if (modulus) {
    // No solid of the range's densest porosity is stiffer than the Hashin-Shtrikman bound.
    const double densest = design_porosity_range(p.design.solid).first;
    const double bound = properties::hashin_shtrikman_upper(1.0 - densest,
                                                            p.material.poisson_ratio)
                             .youngs_modulus *
                         p.material.youngs_modulus_gpa;
    if (t.modulus_gpa >= bound)
      throw std::invalid_argument(fmt::format(
          "--target-modulus: got {} GPa; accepted: below {:.4g} GPa, the Hashin-Shtrikman bound "
          "of any {} of this --material at porosity {} (the densest this design searches)",
          t.modulus_gpa, bound, solid_kind_name(p.design.solid), densest));
  }
  return plan;
}

MonotoneSolve solve_monotone(const std::function<double(double)>& f, double target, double lo,
                             double hi, double x0, double slope_guess, double rel_tol,
                             int max_evaluations) {
  MonotoneSolve s;
  const double goal = std::log(target), tol = std::log1p(rel_tol);
  const double dir = slope_guess > 0 ? 1.0 : -1.0;
  double best = INFINITY;
  // g(x) = log f(x) - log target, increasing in dir * x. The root lies in [b_lo, b_hi];
  // an end is known once evaluated.
  double b_lo = lo, b_hi = hi;
  bool lo_known = false, hi_known = false;
  double g_lo = NAN, g_hi = NAN;
  auto eval = [&](double x) {
    const double v = f(x);
    s.evaluations.emplace_back(x, v);
    const double g = std::log(v) - goal;
    if (std::abs(g) < best) best = std::abs(g), s.x = x, s.value = v;
    if (x == lo) g_lo = g;
    if (x == hi) g_hi = g;
    // The root is above x where g * dir < 0.
    if (g * dir < 0) {
      if (x >= b_lo) b_lo = x, lo_known = true;
    } else if (x <= b_hi) {
      b_hi = x, hi_known = true;
    }
    return g;
  };
  double x = std::clamp(x0, lo, hi);
  double g = eval(x);
  double slope = slope_guess;
  double x_prev = NAN, g_prev = NAN;
  while (std::abs(g) > tol && int(s.evaluations.size()) < max_evaluations) {
    // Beyond an evaluated end of the range: no member reaches the target.
    if ((x == lo && g * dir > 0) || (x == hi && g * dir < 0)) break;
    if (!std::isnan(x_prev) && x != x_prev) {
      const double secant = (g - g_prev) / (x - x_prev);
      if (secant * dir > 0 && std::isfinite(secant)) slope = secant;
    }
    double next = x - g / slope;
    next = std::clamp(next, lo, hi);
    // Inside the bracket, or an end of the range not yet tried; else bisect the bracket.
    const bool inside = next > b_lo && next < b_hi;
    const bool open_end = (next == lo && !lo_known) || (next == hi && !hi_known);
    if (!inside && !open_end) next = 0.5 * (b_lo + b_hi);
    x_prev = x, g_prev = g;
    x = next;
    g = eval(x);
  }
  s.reached = best <= tol;
  if (!s.reached && ((x == lo && g * dir > 0) || (x == hi && g * dir < 0))) {
    // The reachable range: both ends.
    if (std::isnan(g_lo)) eval(lo);
    if (std::isnan(g_hi)) eval(hi);
    s.value_at_lo = std::exp(g_lo + goal);
    s.value_at_hi = std::exp(g_hi + goal);
  }
  return s;
}

double cell_quantity(const Field& phi, TargetQuantity q, SolidKind solid, double porosity,
                     double thickness, const PropertiesRequest& base) {
  PropertiesRequest r = base;
  set_properties_only(r, q == TargetQuantity::kModulus ? "elastic" : "flow");
  if (solid == SolidKind::kSheet)
    set_properties_solid(r, "sheet", 1, std::isnan(thickness) ? porosity : NAN, thickness);
  else
    set_properties_solid(r, "network", 1, NAN, NAN);
  const nlohmann::json j = compute_properties(phi, r);
  if (q == TargetQuantity::kModulus) return mean_of_three(j.at("youngs_modulus_gpa"));
  return mean_of_three(j.at("permeability_m2"));
}

DesignSolution solve_design(const DesignProblem& p, const DesignPlan& plan,
                            const MemberAt& member,
                            const std::function<void(const std::string&)>& progress) {
  const auto t0 = WallClock::now();
  const DesignTargets& t = p.targets;
  DesignSolution s;
  s.porosity = p.design.porosity;
  s.cell_size = p.design.cell_size;
  PropertiesRequest base = p.material;
  base.cell_size = p.design.cell_size;
  base.units = p.design.units;
  const SolidKind solid = p.design.solid;
  nlohmann::json evaluations = nlohmann::json::array();
  nlohmann::json solved, by;
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  if (plan.solve_porosity) {
    const TargetQuantity q = plan.porosity_by;
    const double target = target_of(t, q);
    const auto [lo, hi] = design_porosity_range(solid);
    double x0 = 0.5 * (lo + hi), slope = 0.0;
    if (q == TargetQuantity::kModulus) {
      const double n = modulus_exponent(solid);
      x0 = std::clamp(1.0 - std::pow(2.0 * target / p.material.youngs_modulus_gpa, 1.0 / n), lo,
                      hi);
      slope = -n / (1.0 - x0);
    } else {
      slope = 3.0 / x0 + 2.0 / (1.0 - x0);
    }
    auto f = [&](double porosity) {
      const auto e0 = WallClock::now();
      const Field phi = member(porosity);
      const double v = cell_quantity(phi, q, solid, porosity, NAN, base);
      const double seconds = seconds_since(e0);
      evaluations.push_back({{"porosity", porosity}, {"value", v}, {"seconds", seconds}});
      say(fmt::format("design: porosity {:.4f} -> {} {:.4g} {} (target {:.4g}, {:.1f} s)",
                      porosity, quantity_name(q), v, quantity_unit(q), target, seconds));
      return v;
    };
    const MonotoneSolve m =
        solve_monotone(f, target, lo, hi, x0, slope, p.rel_tol, p.max_evaluations);
    if (!std::isnan(m.value_at_lo))
      throw TargetUnreachable(fmt::format(
          "{}: {:.4g} {} is out of reach of the {} {} at --cell-size {} {}: reachable {:.4g} .. "
          "{:.4g} {} (porosity {} .. {}, the range this design searches){}",
          target_option(q), target, quantity_unit(q), solid_kind_name(solid), "designs",
          p.design.cell_size, p.design.units, std::min(m.value_at_lo, m.value_at_hi),
          std::max(m.value_at_lo, m.value_at_hi), quantity_unit(q), lo, hi,
          q == TargetQuantity::kPermeability
              ? "; a permeability also scales with the cell size squared (--cell-size)"
              : ""));
    s.porosity = m.x;
    solved["porosity"] = m.x;
    by["porosity"] = target_option(q);
    solved["porosity_reached"] = m.reached;
    solved["porosity_value"] = m.value;
  }
  if (plan.cell_size_by_permeability || plan.cell_size_by_pore_size) {
    const auto e0 = WallClock::now();
    const Field phi = member(s.porosity);
    double scale = 1.0, value = NAN;
    if (plan.cell_size_by_permeability) {
      // k in m^2 = k in cell-size^2 times the cell size in metres, squared.
      value = cell_quantity(phi, TargetQuantity::kPermeability, solid, s.porosity, NAN, base);
      scale = std::sqrt(t.permeability_m2 / value);
      by["cell_size"] = "--target-permeability";
    } else {
      ScaffoldDesign d = p.design;
      d.porosity = s.porosity;
      value = design_cell_morphometry(phi, d)["pore_size"]["mean"].get<double>();
      scale = t.pore_size / value;
      by["cell_size"] = "--pore-size";
    }
    s.cell_size = p.design.cell_size * scale;
    const double seconds = seconds_since(e0);
    const char* measured = plan.cell_size_by_permeability ? "permeability_m2" : "pore_size";
    evaluations.push_back(
        {{"cell_size", p.design.cell_size}, {measured, value}, {"seconds", seconds}});
    say(fmt::format("design: at cell size {:.4g} {} the {} is {:.4g} {}: cell size {:.4g} {}",
                    p.design.cell_size, p.design.units,
                    plan.cell_size_by_permeability ? "permeability" : "mean pore size", value,
                    plan.cell_size_by_permeability ? "m^2" : p.design.units, s.cell_size,
                    p.design.units));
    if (!(s.cell_size >= kMinCellSize && s.cell_size <= kMaxCellSize))
      throw TargetUnreachable(fmt::format(
          "{}: needs a cell size of {:.4g} {}; accepted: {:g} .. {:g}",
          std::string(by["cell_size"]), s.cell_size, p.design.units, kMinCellSize,
          kMaxCellSize));
    solved["cell_size"] = s.cell_size;
  }
  nlohmann::json targets;
  if (!std::isnan(t.modulus_gpa)) targets["modulus_gpa"] = t.modulus_gpa;
  if (!std::isnan(t.permeability_m2)) targets["permeability_m2"] = t.permeability_m2;
  if (!std::isnan(t.pore_size)) targets["pore_size"] = t.pore_size;
  if (!std::isnan(t.min_wall)) targets["min_wall"] = t.min_wall;
  s.report = {{"targets", targets},
              {"solved", solved},
              {"solved_by", by},
              {"evaluations", evaluations},
              {"seconds", seconds_since(t0)}};
  return s;
}

nlohmann::json confirm_design(const DesignProblem& p, const Field& phi,
                              const nlohmann::json& part_report,
                              std::vector<std::string>& warnings) {
  const DesignTargets& t = p.targets;
  const auto t0 = WallClock::now();
  nlohmann::json achieved;
  PropertiesRequest base = p.material;
  base.cell_size = p.design.cell_size;
  base.units = p.design.units;
  const double thickness = part_report.contains("sheet")
                               ? part_report["sheet"]["thickness"].get<double>()
                               : NAN;
  auto entry = [](double value, double target) {
    return nlohmann::json{{"value", value},
                          {"target", target},
                          {"relative_error", value / target - 1.0}};
  };
  for (TargetQuantity q : {TargetQuantity::kModulus, TargetQuantity::kPermeability}) {
    const double target = target_of(t, q);
    if (std::isnan(target) || phi.n() == 0) continue;
    const double v = cell_quantity(phi, q, p.design.solid, NAN, thickness, base);
    achieved[q == TargetQuantity::kModulus ? "modulus_gpa" : "permeability_m2"] =
        entry(v, target);
  }
  const nlohmann::json& m = part_report.at("morphometry");
  if (!std::isnan(t.pore_size) && m.contains("pore_size"))
    achieved["pore_size"] = entry(m["pore_size"]["mean"].get<double>(), t.pore_size);
  if (!std::isnan(t.min_wall)) {
    // The thinnest wall a designer can trust: the 5th percentile (of each member when graded).
    double p5 = INFINITY;
    if (m.contains("wall_thickness")) p5 = m["wall_thickness"]["p5"].get<double>();
    if (m.contains("members"))
      for (const auto& c : m["members"]) p5 = std::min(p5, c["wall_thickness"]["p5"].get<double>());
    if (std::isfinite(p5)) {
      const bool met = p5 >= t.min_wall;
      achieved["min_wall"] = {{"wall_p5", p5}, {"min_wall", t.min_wall}, {"met", met}};
      if (!met) {
        const std::string why = fmt::format(
            "--min-wall: the thinnest wall (5th percentile of the wall thickness) is {:.4g} {}, "
            "below {} {}; a lower porosity or a larger cell size thickens it",
            p5, p.design.units, t.min_wall, p.design.units);
        if (t.strict_min_wall) throw TargetUnreachable(why + " (--strict-min-wall: not written)");
        warnings.push_back(why);
      }
    }
  }
  achieved["seconds"] = seconds_since(t0);
  return achieved;
}

}  // namespace cmcsurf
