// cmcsurf schema --json: the report schema (schema/report_schema.h) as JSON, for the scripts
// and tests that read report.json, history.csv and sweep.csv (scripts/sweep_table.py,
// tests/support/report_keys.py). Not listed in --help: a tool's command, not a user's.
#include <cstdio>
#include <memory>

#include "commands.h"
#include "schema/report_schema.h"

namespace cmcsurf::cli {

CommandFn add_schema_command(CLI::App& root) {
  CLI::App* app = root.add_subcommand(
      "schema", "The report keys, history.csv's and sweep.csv's columns, as JSON");
  app->group("");  // hidden
  auto json = std::make_shared<bool>(false);
  app->add_flag("--json", *json, "Print the tables as JSON (the only form)")->required();
  // The flag's bool lives as long as the command (CLI11 writes it while parsing).
  return {app, [json]() -> int {
            (void)json;
            std::fputs(report_schema_json().c_str(), stdout);
            return std::fflush(stdout) == 0 ? 0 : 1;
          }};
}

}  // namespace cmcsurf::cli
