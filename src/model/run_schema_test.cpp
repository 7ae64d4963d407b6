#include "model/run_schema.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "cahn_hilliard/time_step.h"
#include "io/run_report.h"
#include "multigrid/fas.h"
#include "model/run_options.h"

namespace cmcsurf {
namespace {

// p with entry o's value changed to another value of its type (not necessarily in range).
RunParams changed(const RunOption& o, RunParams p) {
  std::visit(
      [&](const auto& ref) {
        using R = std::decay_t<decltype(ref)>;
        if constexpr (std::is_same_v<R, RunChoice>) {
          ref.set(p, (ref.get(p) + 1) % int(ref.names.size()));
        } else {
          auto& v = ref(p);
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, bool>) v = !v;
          else if constexpr (std::is_same_v<T, std::string>) v += "x";
          else if constexpr (std::is_same_v<T, double>) v = v * 2.0 + 0.125;
          else v = v + 1;
        }
      },
      o.ref);
  return p;
}

// The number of members of an aggregate: the most initializers T{...} takes.
struct AnyMember {
  template <class U>
  operator U() const;
};
template <class T, class... A>
constexpr std::size_t aggregate_members() {
  if constexpr (requires { T{A{}..., AnyMember{}}; })
    return aggregate_members<T, A..., AnyMember>();
  else
    return sizeof...(A);
}

std::vector<std::string> differing_keys(const nlohmann::json& a, const nlohmann::json& b) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : a.items())
    if (!b.contains(key) || b.at(key) != value) keys.push_back(key);
  return keys;
}

TEST(RunSchema, KeysAndCommandLineNamesAreUnique) {
  std::set<std::string> keys, names;
  for (const RunOption& o : run_option_table()) {
    EXPECT_TRUE(keys.insert(o.key).second) << o.key;
    if (*o.cli != '\0') {
      EXPECT_TRUE(names.insert(o.name()).second) << o.name();
    }
    EXPECT_EQ(find_run_option(o.key), &o);
    EXPECT_NE(std::string(o.help), "") << o.key;
  }
  EXPECT_EQ(find_run_option("no_such_option"), nullptr);
}

// A tripwire: a member added to RunParams, or to the solver options it holds, changes these
// counts. Give it an entry in model/run_schema.cpp (or say here why it is no parameter), then
// update the count.
TEST(RunSchema, EveryParameterMemberHasAnEntry) {
  EXPECT_EQ(aggregate_members<RunParams>(), 34u);  // 33 entries and `solver`
  EXPECT_EQ(aggregate_members<StepSolverOptions>(), 7u);  // 4 entries, `fas`, and
  // divergence_factor and restore_mass, which only tests change
  EXPECT_EQ(aggregate_members<FasOptions>(), 5u);  // 4 entries; coarsest_check_every: cost only
  EXPECT_EQ(run_option_table().size(), 33u + 4u + 4u);
}

// Each entry reads and writes its own member: changing one changes exactly its key in
// params_json (two entries on one member, or one on the wrong member, would show here), and
// params_json holds exactly the table's keys.
TEST(RunSchema, EachEntryIsItsOwnMemberAndKey) {
  const RunParams base;
  const nlohmann::json j = params_json(base);
  EXPECT_EQ(j.size(), run_option_table().size());
  for (const RunOption& o : run_option_table()) {
    EXPECT_TRUE(j.contains(o.key)) << o.key;
    const RunParams q = changed(o, base);
    EXPECT_EQ(differing_keys(params_json(q), j), std::vector<std::string>{o.key}) << o.key;
    EXPECT_NE(run_option_value(o, q), run_option_value(o, base)) << o.key;
  }
}

// Resume's check walks the whole table and compares by key: every option given with another
// value is found, whatever the command line calls it (renamed or without a CLI name), and an
// option given with the saved value, or not given, is not.
TEST(RunSchema, ResumeComparesEveryOptionByItsKey) {
  const RunParams saved;
  std::vector<RunOption> renamed(run_option_table().begin(), run_option_table().end());
  std::vector<std::string> names(renamed.size());
  for (std::size_t i = 0; i < renamed.size(); ++i) {
    names[i] = i % 2 == 0 ? "--renamed-" + std::to_string(i) : "";
    renamed[i].cli = names[i].c_str();
  }
  for (std::size_t i = 0; i < renamed.size(); ++i) {
    const RunOption& o = run_option_table()[i];
    const RunParams mine = changed(o, saved);
    auto only = [&](const RunOption& e) { return std::string(e.key) == o.key; };
    EXPECT_EQ(changed_run_option(mine, saved, only), &o) << o.key;
    EXPECT_EQ(changed_run_option(mine, saved, only, renamed), &renamed[i]) << o.key;
    EXPECT_EQ(changed_run_option(saved, saved, only), nullptr) << o.key;
    EXPECT_EQ(changed_run_option(mine, saved, [](const RunOption&) { return false; }), nullptr);
  }
}

// The defaults are inside the declared ranges, and a value just outside either end is refused
// with the message that names the option (check_run_params, as the command line prints it).
TEST(RunSchema, RangesRefuseJustOutsideWithTheOptionsName) {
  const RunParams base;
  int checked = 0;
  for (const RunOption& o : run_option_table()) {
    if (*o.accepted == '\0') continue;
    const bool integer = std::holds_alternative<RunMember<int>>(o.ref);
    const double v = std::get<double>(std::visit(
        [](const auto& x) -> RunOptionValue {
          if constexpr (std::is_arithmetic_v<std::decay_t<decltype(x)>>) return double(x);
          return 0.0;
        },
        run_option_value(o, base)));
    EXPECT_TRUE(o.range.contains(v)) << o.key << " default " << v;
    for (const bool low : {true, false}) {
      const double end = low ? o.range.lo : o.range.hi;
      if (!std::isfinite(end)) continue;
      const bool closed = low ? o.range.lo_closed : o.range.hi_closed;
      const double step = integer ? 1.0 : 0.0;
      const double toward = low ? -std::numeric_limits<double>::infinity()
                                : std::numeric_limits<double>::infinity();
      const double bad = !closed ? end
                         : integer ? end + (low ? -step : step)
                                   : std::nextafter(end, toward);
      RunParams p = base;
      if (integer)
        std::get<RunMember<int>>(o.ref)(p) = int(bad);
      else
        std::get<RunMember<double>>(o.ref)(p) = bad;
      try {
        check_run_params(p, true);
        ADD_FAILURE() << o.key << " = " << bad << " accepted";
      } catch (const OptionError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(o.name() + ": got ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find(o.accepted), std::string::npos) << e.what();
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 30);
}

// --fast sets each option it chooses unless that option was given; the choices' names are
// converted, an unknown one refused naming the option and its names.
TEST(RunSchema, FastChoosesWhatWasNotGivenAndNamesConvert) {
  RunParams p;
  p.grid = 128;
  p.fast = true;
  p.settle_tol = 1e-3;
  RunChoices c;
  c.given = {"settle_tol"};
  c.text = {{"stop", "phi"}, {"smoother", "lex"}};
  finish_run_params(p, c, true);
  EXPECT_EQ(p.settle_tol, 1e-3);
  EXPECT_EQ(p.solver.rtol, kFastMgRtol);
  EXPECT_EQ(p.mg_rtol_finest, kFastMgRtolFinest);
  EXPECT_EQ(p.dt_max_factor, kFastDtMaxFactor);
  EXPECT_TRUE(p.solver.extrapolate);
  EXPECT_EQ(p.coarse_levels, 2);  // 128 -> 32
  EXPECT_EQ(p.stop, StopRule::kPhi);
  EXPECT_EQ(p.smoother, SweepOrder::kLexicographic);

  RunParams q;
  c = {};
  c.text = {{"constrain", "area"}};
  try {
    finish_run_params(q, c, true);
    ADD_FAILURE() << "constrain area accepted";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(), "--constrain: got 'area'; accepted: volume, mass, components");
  }
  RunParams slow;  // without --fast nothing is chosen
  slow.fast = false;
  const nlohmann::json unchanged = params_json(slow);
  finish_run_params(slow, {}, true);
  EXPECT_EQ(params_json(slow), unchanged);
}

// The defaults are the fast mode at 128^3 (epsilon 0.01 = 1.28 h) ending on the equilibrium
// rule; --paper gives back the paper-faithful run exactly as the defaults were before (64^3,
// nothing chosen), a given --grid stays, and --paper with --fast is refused.
TEST(RunSchema, DefaultsAreFastAndResolvedPaperIsTheOldRun) {
  RunParams fast;
  finish_run_params(fast, {}, true);
  EXPECT_EQ(fast.grid, 128);
  EXPECT_GE(fast.epsilon * fast.grid, 1.28 - 1e-12);
  EXPECT_TRUE(fast.fast);
  EXPECT_EQ(fast.equilibrium_tol, kFastEquilibriumTol);  // at 128^3; (128/N)^2 times that at N
  EXPECT_EQ(fast_equilibrium_tol(256), 0.25 * kFastEquilibriumTol);
  EXPECT_EQ(fast.settle_tol, 0.0);
  EXPECT_EQ(fast.coarse_levels, 2);
  EXPECT_EQ(fast.anderson_depth, kFastAndersonDepth);
  EXPECT_EQ(fast.continued_dt_factor, kFastContinuedDtFactor);  // no ramp on a continued grid

  RunParams paper;
  paper.paper = true;
  finish_run_params(paper, {}, true);
  RunParams before;  // the defaults before the fast mode was
  before.grid = kPaperGrid;
  before.fast = false;
  before.paper = true;
  EXPECT_EQ(params_json(paper), params_json(before));
  EXPECT_EQ(paper.grid, 64);
  EXPECT_EQ(paper.equilibrium_tol, 0.0);
  EXPECT_EQ(paper.solver.rtol, 0.0);
  EXPECT_EQ(paper.stop, StopRule::kArea);

  RunParams grid;
  grid.paper = true;
  grid.grid = 32;
  RunChoices c;
  c.given = {"grid"};
  finish_run_params(grid, c, true);
  EXPECT_EQ(grid.grid, 32);

  RunParams both;
  both.paper = true;
  c.given = {"fast"};
  try {
    finish_run_params(both, c, true);
    ADD_FAILURE() << "--paper with --fast accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--paper: not with --fast", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace cmcsurf
