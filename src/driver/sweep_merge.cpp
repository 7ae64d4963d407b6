#include "driver/sweep_merge.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "driver/families_figure.h"
#include "model/run_options.h"
#include "report/run_page.h"
#include "driver/sweep_driver.h"

namespace cmcsurf {

namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path) {
  require_regular_file(path, "JSON file");
  std::ifstream in(path);
  if (!in) throw OptionError(fmt::format("{}: cannot open", path.string()));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw OptionError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
}

template <class T>
void add_once(std::vector<T>& list, const T& v) {
  if (std::find(list.begin(), list.end(), v) == list.end()) list.push_back(v);
}

}  // namespace

MergePlan plan_merge(const std::vector<fs::path>& sources) {
  if (sources.size() < 2)
    throw OptionError(fmt::format("merge: got {} sweep folder(s); accepted: two or more",
                                  sources.size()));
  std::vector<SweepJson> read;
  for (const fs::path& dir : sources) {
    const fs::path file = dir / "sweep.json";
    nlohmann::json j;
    try {
      j = read_json(file);
    } catch (const std::runtime_error& e) {
      throw OptionError(fmt::format("merge: {}: no sweep folder ({})", dir.string(), e.what()));
    }
    try {
      read.push_back(parse_sweep_json(j));
    } catch (const std::invalid_argument& e) {
      throw OptionError(fmt::format("merge: {}: {}", file.string(), e.what()));
    }
    if (!j.value("complete", false))
      throw OptionError(fmt::format("merge: {}: the sweep is not complete (finish it with "
                                    "`cmcsurf sweep --resume {}`)",
                                    file.string(), dir.string()));
    for (const std::string& s : read.back().sweep.surfaces)
      if (s.rfind("expr:", 0) == 0)
        throw OptionError(fmt::format("merge: {}: surface '{}': expr: members are named by "
                                      "their position in a sweep (expr0, ...); accepted: named "
                                      "nodal surfaces (P, D, G, ...)",
                                      file.string(), s));
  }
  MergePlan plan;
  SweepParams& sp = plan.sweep;
  sp.run = read[0].sweep.run;
  sp.continuation = read[0].sweep.continuation;
  plan.outputs = read[0].outputs;
  const nlohmann::json first = params_json(sp.run);
  for (std::size_t k = 1; k < read.size(); ++k) {
    const nlohmann::json other = params_json(read[k].sweep.run);
    for (const auto& [key, value] : first.items()) {
      if (key == "surface" || key == "volume_fraction") continue;  // per member
      if (!other.contains(key) || other[key] != value)
        throw OptionError(fmt::format(
            "merge: {} has {} {}, {} has {}; a merged sweep's members share their run "
            "parameters",
            sources[k].string(), key, other.value(key, nlohmann::json()).dump(),
            sources[0].string(), value.dump()));
    }
    if (read[k].sweep.continuation != sp.continuation)
      throw OptionError(fmt::format("merge: {} and {} differ in --continuation",
                                    sources[k].string(), sources[0].string()));
  }
  for (const SweepJson& j : read) {
    for (const std::string& s : j.sweep.surfaces) add_once(sp.surfaces, s);
    for (double a : j.sweep.fractions) add_once(sp.fractions, a);
  }
  try {
    check_sweep_params(sp);
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("merge: {}", e.what()));
  }
  for (const std::string& s : sp.surfaces)
    for (double a : sp.fractions) {
      std::vector<std::size_t> in;
      for (std::size_t k = 0; k < read.size(); ++k) {
        const SweepParams& q = read[k].sweep;
        if (std::find(q.surfaces.begin(), q.surfaces.end(), s) != q.surfaces.end() &&
            std::find(q.fractions.begin(), q.fractions.end(), a) != q.fractions.end())
          in.push_back(k);
      }
      const std::string name = member_name(s, 0, a);
      if (in.empty())
        throw OptionError(fmt::format(
            "merge: no source has member {} (surface {}, volume fraction {}); the merged sweep "
            "is every surface at every volume fraction, so each must be in one source",
            name, s, a));
      if (in.size() > 1)
        throw OptionError(fmt::format("merge: member {} is in {} and {}; accepted: each member "
                                      "in one source",
                                      name, sources[in[0]].string(), sources[in[1]].string()));
      plan.origin.push_back(in[0]);
    }
  if (sp.continuation) {  // a family continues from its own members: one source, its order
    for (std::size_t s = 0; s < sp.surfaces.size(); ++s) {
      const std::size_t k = plan.origin[s * sp.fractions.size()];
      for (std::size_t f = 0; f < sp.fractions.size(); ++f)
        if (plan.origin[s * sp.fractions.size() + f] != k ||
            read[k].sweep.fractions != sp.fractions)
          throw OptionError(fmt::format(
              "merge: with --continuation each family is computed in one sweep over the same "
              "volume fractions; {}'s family is not",
              sp.surfaces[s]));
    }
  }
  return plan;
}

nlohmann::json write_merged_sweep(const std::vector<fs::path>& sources, const MergePlan& plan,
                                  const fs::path& out, const MergeOptions& options) {
  const SweepParams& sp = plan.sweep;
  std::vector<nlohmann::json> reports;
  double wall = 0.0;
  for (const fs::path& src : sources)
    wall += read_json(src / "sweep.json").value("wall_seconds", 0.0);
  int index = 0;
  for (std::size_t s = 0; s < sp.surfaces.size(); ++s)
    for (double alpha : sp.fractions) {
      const std::string name = member_name(sp.surfaces[s], int(s), alpha);
      const fs::path from = sources[plan.origin[std::size_t(index++)]] / name;
      nlohmann::json report = read_json(from / "report.json");
      std::error_code ec;
      fs::remove_all(out / name, ec);
      fs::copy(from, out / name, fs::copy_options::recursive, ec);
      if (ec)
        throw std::runtime_error(fmt::format("merge: cannot copy {} to {}: {}", from.string(),
                                             (out / name).string(), ec.message()));
      reports.push_back(std::move(report));
    }
  write_file_atomic(out / "sweep.csv", sweep_csv(reports));
  nlohmann::json summary =
      sweep_summary(sp, plan.outputs, reports.size(), plan.outputs.value("threads", 0), wall);
  summary["complete"] = true;
  summary["literature"] = literature_json();
  nlohmann::json from = nlohmann::json::array();
  for (const fs::path& src : sources) from.push_back(src.string());
  summary["merged_from"] = from;
  if (options.figures)
    if (nlohmann::json f = write_families_figure(out, reports, options.diffuse); !f.is_null())
      summary["families_figure"] = std::move(f);
  write_json_atomic(out / "sweep.json", summary);
  if (options.page && !plan.outputs.value("no_preview", false)) {
    summary["gallery_seconds"] = write_gallery_from_folder(out);
    write_json_atomic(out / "sweep.json", summary);
  }
  if (options.page && !plan.outputs.value("no_report", false)) write_sweep_page(out);
  return summary;
}

}  // namespace cmcsurf
