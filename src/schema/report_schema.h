// The names a user reads in a run's outputs, each declared once with its label, unit, format
// and help: report.json's keys, history.csv's columns (and the stages in its "stage" column)
// and sweep.csv's leading columns. The run page and the sweep page (report/run_page.cpp), the
// command line's summaries, the history writer and reader (io/run_report.cpp,
// io/checkpoint.cpp), sweep.csv (io/run_report.cpp), Python's history (python/src/module.cpp),
// scripts/sweep_table.py and the tests' timing keys (tests/support/report_keys.py, through
// `cmcsurf schema --json`) read these tables instead of spelling the names. Plain data: no
// other layer of cmcsurf is included.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cmcsurf {

// A column of a table that shows some of the keys: its heading and the format of its numbers
// (fmt's, "{:+.3%}" a percentage: see format_report_number). An empty heading: not shown.
struct ColumnView {
  std::string_view header = {};
  std::string_view format = {};
};

// Where the run page (report.html) shows a key.
enum class PageTable {
  kNone,
  kKeyNumbers,  // the "Key numbers" table, in the order of report_key_table()
};

// One key of report.json.
struct ReportKey {
  std::string_view key = {};
  std::string_view label = {};  // the run page's row heading
  std::string_view unit = {};   // "s", "bytes"; "": a number in the cell's units, a count or a name
  // What it means; with `convention` also report.json's "conventions" entry for it.
  std::string_view help = {};
  bool convention = false;
  std::string_view format = {};  // the page's format of a number that is not an integer
  PageTable page = PageTable::kNone;
  std::string_view error_key = {};  // its error estimate, shown after it as " ± 5.8e-03"
  // Depends on the machine, the clock or where a run was interrupted and resumed, not on the
  // surface computed: tests that compare two runs of one surface ignore it.
  bool timing = false;
  std::string_view summary = {};      // its format in `cmcsurf run`'s closing summary
  std::string_view member_line = {};  // its format in a sweep's line per member
  ColumnView sweep_page = {};         // the sweep page's table of members (in this table's order)
};

// Every key above, in the run page's order (keys not on the page after it).
const std::vector<ReportKey>& report_key_table();
// The entry of `key`; a key the table lacks is a programmer's error (std::logic_error).
const ReportKey& report_key(std::string_view key);
// The keys with `timing` set, sorted.
std::vector<std::string> timing_report_keys();

// A number as `format` says ("{:.4g}"); "{:+.4%}" prints 100 x with a "%" (fmt has no % type).
std::string format_report_number(std::string_view format, double x);
// A number in report_key(key)'s format for `cmcsurf run`'s summary and a sweep's member line.
std::string summary_number(std::string_view key, double x);
std::string member_line_number(std::string_view key, double x);

// ---- history.csv -------------------------------------------------------------------------

// The stages of a run (Section 4.4) that a step belongs to and a checkpoint resumes in.
enum class RunStage {
  kPrerelax,  // step 3, at the wide epsilon
  kRelax,     // step 6
  kVolume,    // the relaxations after the volume constraint's mass corrections
};
// "prerelax", "relax", "volume": history.csv's, the progress line's and the checkpoint's word.
std::string_view run_stage_name(RunStage s);
// The inverse; nullopt for any other text.
std::optional<RunStage> parse_run_stage(std::string_view name);

enum class HistoryColumn {
  kStep, kStage, kTime, kArea, kDArea, kDPhi, kEnergy, kMass, kVcycles, kResidual, kElapsed,
  kDt, kVolumeFraction, kEquilibriumResidual,
};
enum class HistoryType { kInt, kText, kNumber };

struct HistoryColumnInfo {
  HistoryColumn id = HistoryColumn::kStep;
  std::string_view name = {};    // history.csv's header, the checkpoint's key, Python's dict key
  HistoryType type = HistoryType::kNumber;
  std::string_view format = {};  // history.csv's format of the value
  std::string_view unit = {};
  std::string_view help = {};
  bool timing = false;      // as ReportKey::timing
};

// history.csv's columns in its order (also Python's Result.history and progress dicts).
const std::vector<HistoryColumnInfo>& history_column_table();
// "step,stage,time,...": history.csv's first line, without the newline.
std::string history_header();
// "step, stage, time, ...": the column names for a doc string.
std::string history_column_list();

// ---- sweep.csv ---------------------------------------------------------------------------

// sweep.csv's first columns, in order (each a key of report_key_table()); every other
// top-level scalar key of the members' reports follows them, in the order the reports have.
const std::vector<std::string_view>& sweep_leading_columns();

// The families tables of scripts/sweep_table.py (docs/families.md): one column per entry, a
// report key (a column of sweep.csv) with its heading and format, in this order.
struct FamiliesColumn {
  std::string_view key = {};
  ColumnView view = {};
};
const std::vector<FamiliesColumn>& families_table_columns();

// ---- keys below report.json's top level, and sweep.json's -------------------------------

// A key inside one of report.json's dictionaries, or of sweep.json, named by its path from the
// top with dots ("crystallographic_cell.computed_cell.area"); "[]" stands for the items of a
// list of dictionaries ("interfaces[].area"). A dictionary with the keys of another names it in
// `like` ("properties.nodal" like "properties"), so that they are declared once.
struct NestedKey {
  std::string_view path = {};
  std::string_view label = {};  // a page's or a chart's heading
  std::string_view unit = {};   // as ReportKey::unit
  std::string_view help = {};
  bool timing = false;  // as ReportKey::timing
  std::string_view like = {};
};

// The keys inside report.json's dictionaries that the pages and Python read
// (crystallographic_cell, properties, checkpoint, bisection, interfaces): a dictionary with an
// entry here is declared key by key (`cli.report_reference` fails on a key written but not
// declared); one without (parameters, build, conventions, initial) is its top-level entry.
const std::vector<NestedKey>& nested_report_key_table();
// sweep.json's keys (driver/sweep_driver.cpp), its top level and its dictionaries alike.
const std::vector<NestedKey>& sweep_json_key_table();

// ---- the dump ----------------------------------------------------------------------------

// All of the above as JSON text (`cmcsurf schema --json`; scripts and tests read it):
// {"report_keys": [{key, label, unit, help, convention, format, page, error_key, timing,
// summary, member_line, sweep_page: {header, format}}...], "history_columns": [{name, type,
// format, unit, help, timing}...], "stages": [...], "sweep_leading_columns": [...],
// "families_table": [{key, header, format}...], "nested_report_keys": [{path, label, unit,
// help, timing, like}...], "sweep_json_keys": [the same]}.
std::string report_schema_json();

}  // namespace cmcsurf
