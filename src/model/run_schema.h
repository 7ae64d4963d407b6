// The run options in one table: the options of `cmcsurf run` (also of `sweep` and of Python's
// run, relax and sweep) and the keys of report.json's `parameters`. Each entry names one
// option once; the command line (apps/cli_common.cpp), the range checks
// (model/run_options.cpp), the JSON round trip (io/run_report.cpp), resume's comparison
// and the Python keywords (python/src/module.cpp) walk this table instead of spelling it.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "model/run.h"

namespace cmcsurf {

// A RunParams member an entry reads and writes (a function, since some are nested).
template <class T>
using RunMember = T& (*)(RunParams&);

// An enumeration of RunParams stored by name ("area", "phi"): names[i] is value i.
struct RunChoice {
  std::vector<const char*> names;
  int (*get)(const RunParams&);
  void (*set)(RunParams&, int);
};

using RunOptionRef = std::variant<RunMember<double>, RunMember<int>, RunMember<std::uint64_t>,
                                  RunMember<std::string>, RunMember<bool>, RunChoice>;

// Which commands take an option.
enum class RunOptionScope {
  kSurface,   // run only: surface, volume_fraction (a sweep has lists of them)
  kInitial,   // the initial field of sphere and noise: run and sweep's command line, Python run
  kGrid,      // not Python's relax (the given field's grid)
  kSolver,    // every command that runs
  kInternal,  // a key of the parameters only: no option of the command line or Python
};

// A number's accepted range: lo <(=) value <(=) hi; NaN is never inside.
struct RunRange {
  double lo, hi;
  bool lo_closed, hi_closed;
  bool contains(double v) const {
    return (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
};

struct RunOption {
  const char* key;   // report.json's `parameters`, checkpoints, sweep.json; Python's keyword
  const char* cli;   // the CLI11 name ("--grid", "--extrapolate,!--no-extrapolate"); "": none
  const char* help;  // the command line's help text
  const char* unit;  // "": a pure number or a name
  RunOptionScope scope;
  bool solver_group;  // listed under the command line's "solver" heading
  RunOptionRef ref;
  // The accepted range and how a message states it ("0 < E < 1"); for numbers only. An entry
  // without `accepted` is checked by check_run_params itself (it depends on other options).
  RunRange range{};
  const char* accepted = "";
  // --fast's value, set where the option was not given (null: --fast leaves it alone).
  void (*fast)(RunParams& p, bool check_surface) = nullptr;
  // --paper's value, set where the option was not given (null: --paper leaves it alone).
  void (*paper)(RunParams& p) = nullptr;
  // Absent from files written before the option existed: the default then.
  bool optional_in_json = false;
  // A library check of an integer's text before it is stored (--seed's sign); null: none.
  std::string (*integer_check)(long long) = nullptr;

  // "--grid" (the first long name), or the key where the command line has no such option:
  // how messages name the option.
  std::string name() const;
  bool python() const { return scope != RunOptionScope::kInternal; }
};

// Every run option, in the command line's order (its help lists them so).
std::span<const RunOption> run_option_table();
// The entry of a key; null for none.
const RunOption* find_run_option(const std::string& key);

// An entry's value in p: numbers as double, integers as long long (seed as uint64), choices by
// name. For the comparison of two parameter sets, messages and Python's defaults.
using RunOptionValue = std::variant<double, long long, std::uint64_t, std::string, bool>;
RunOptionValue run_option_value(const RunOption& o, const RunParams& p);
// Sets a choice by name; false (p unchanged) when the name is none of its names.
bool set_run_choice(const RunOption& o, RunParams& p, const std::string& name);
// "area, phi"
std::string run_choice_names(const RunOption& o);

// The first option of `table`, in its order, that was given (`given(o)`) and whose value
// differs between `mine` and `saved`; null when none. Resume refuses it: a resumed run keeps
// the parameters it started with. Every entry is compared, whatever its CLI name.
const RunOption* changed_run_option(const RunParams& mine, const RunParams& saved,
                                    const std::function<bool(const RunOption&)>& given,
                                    std::span<const RunOption> table = run_option_table());

}  // namespace cmcsurf
