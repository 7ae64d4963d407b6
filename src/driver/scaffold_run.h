// `cmcsurf scaffold` and Python's cmcsurf.scaffold() as one library call (docs/scaffolds.md):
// the options as a plain struct with their table (the command line's names and help, Python's
// keywords and defaults), the checks with their messages, and the driver that computes (or
// reuses from its cache) the CMC members, designs the part, writes FILE, FILE.json, FILE.html
// and FILE.png, and returns FILE.json as written. The command line and Python only translate.
#pragma once

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/decimate.h"
#include "pipeline/cmc.h"
#include "model/run_options.h"

namespace cmcsurf {

// What the user asked for; every member but `given` is an entry of scaffold_option_table(),
// whose default is the member's initializer.
struct ScaffoldOptions {
  std::string out;        // the mesh file; FILE.json, FILE.html, FILE.png beside it
  std::string surface = "G";
  std::string porosity;   // P, or A:B ramped along `axis`
  std::string axis = "z";
  std::string grade_by = "axis";  // axis, or surface: a --shape's depth (grade_depth)
  double grade_depth = 0.0;       // units; 0: one cell size
  int graded_members = 0;  // 0: one per 0.1 of porosity, at least 2
  std::string solid = "network";
  std::string cell_size = "2";  // S, or A:B graded along `axis` (a network)
  std::string size = "10";
  std::string shape;
  double skin = 0.0;
  std::string units = "mm";
  std::string format;
  std::string cache;       // "": $XDG_CACHE_HOME/cmcsurf or ~/.cache/cmcsurf
  bool keep_fragments = false;
  long max_triangles = 0;
  double tolerance = 0.0;
  double resolution = 0.0;  // voxel size in units (0: the grid decides)
  double min_feature = 0.0;
  bool compare_nodal = false;
  bool properties = false;
  std::string material;     // E_GPa[,nu]
  bool accept_topology_change = false;
  std::string target_modulus, target_permeability;  // V or A:B along `axis`
  double pore_size = NAN, min_wall = NAN;
  bool strict_min_wall = false;
  bool no_page = false;
  // The keys the user gave (a default differs from the same value typed for cell_size, size,
  // tolerance; the run options' given keys are in RunChoices).
  std::set<std::string> given;
};

using ScaffoldMember =
    std::variant<std::string ScaffoldOptions::*, double ScaffoldOptions::*,
                 int ScaffoldOptions::*, long ScaffoldOptions::*, bool ScaffoldOptions::*>;

// One option: its key (Python's keyword), its command-line name, help and member.
struct ScaffoldOption {
  std::string key, cli, help;
  ScaffoldMember member;
  const char* type() const;  // "str", "float", "int", "bool"
};
const std::vector<ScaffoldOption>& scaffold_option_table();

// Sets one option from a JSON value (a number, a string, a bool; null: left at its default),
// recording it as given; OptionError naming the option and the type accepted.
void set_scaffold_option(ScaffoldOptions& o, const ScaffoldOption& option,
                         const nlohmann::json& value);
// A run option (model/run_schema.h) by key from a JSON value, as set_scaffold_option;
// null leaves it to --fast or --paper. OptionError for an unknown key or a wrong type.
void set_run_option_json(RunParams& p, RunChoices& c, const std::string& key,
                         const nlohmann::json& value);
// The table with its defaults: [{key, cli, help, type, default}] (Python's signature).
nlohmann::json scaffold_option_schema();

// Run-time handles: none changes the part.
struct ScaffoldContext {
  std::function<void(const std::string&)> say;   // progress and notes, a line each (none: quiet)
  std::function<void(const StepRecord&)> step;   // the members' time steps
  std::function<void()> steps_done;              // after each member's solve
  DecimateProgress decimate;                     // the decimation's
  // Polled before each time step of a member, with each line said and during the decimation
  // (Python's Ctrl-C): true stops the call with ScaffoldInterrupted, nothing written.
  std::function<bool()> stop;
  int threads = 1;                               // in use, for FILE.json
};

// ScaffoldContext::stop said so: the call ended early and wrote nothing (a member being
// computed is not cached).
struct ScaffoldInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What make_scaffold wrote and measured; const once returned.
// The member's grid without --grid or --resolution (fast mode): the part's lattice is the
// member's grid tiled, so the run's default (128) made the default 10 mm part of 2 mm cells
// 640^3 nodes, 113M triangles, 24 GB and more than ten minutes of decimation (measured). At
// 32 the lattice spacing is cell / 32 (62.5 um for 2 mm cells, about a printer's voxel). The
// run's epsilon (0.01) stays: the 1.28 h that resolves the interface at 32 (0.04) lost G
// networks at porosity 0.8 and above (the wide pre-relaxation emptied the phase; measured).
inline constexpr int kScaffoldGrid = 32;

struct ScaffoldRun {
  nlohmann::json report;              // FILE.json as written
  std::vector<std::string> warnings;  // also in the report's "warnings" where it has them
  std::filesystem::path out, page, preview;  // page and preview empty with no_page
  double page_seconds = 0.0;
};

// No part can be made from these options (a target out of reach, a cell size the box cannot
// hold, closed cells): nothing is written (exit 1 on the command line).
struct ScaffoldFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Checks every option before any work (OptionError naming the option and what is accepted),
// computes or reuses the members, builds, measures and writes the part. `params` and `choices`
// hold the run options (finish_run_params is applied here, after the member's volume fraction
// is known). Throws ScaffoldFailed (or TargetUnreachable, ClosedCellError, both ScaffoldFailed's
// kin as std::runtime_error) when there is no part.
ScaffoldRun make_scaffold(const ScaffoldOptions& o, RunParams params, const RunChoices& choices,
                          const ScaffoldContext& context);

// The morphometry of one unit cell of a field (cmcsurf.morphometry): a network (phase 1 of phi)
// or a sheet at `porosity` or `thickness` (one of them; output units), cell_size wide in units:
// `wall_thickness`, `pore_size` (p5/p50/p95, min, mean, std), `throat`, `porosity`.
nlohmann::json cell_morphometry(const Field& phi, const std::string& solid, double porosity,
                                double thickness, double cell_size, const std::string& units);

}  // namespace cmcsurf
