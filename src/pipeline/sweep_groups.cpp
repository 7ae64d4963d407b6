#include "pipeline/sweep_groups.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "multigrid/fas.h"
#include "parallel/decomposition.h"

namespace cmcsurf {

namespace {

// A vector of plain values as a MessagePack binary (the processes of one run share a byte order).
template <class T>
nlohmann::json binary_of(const std::vector<T>& v) {
  std::vector<std::uint8_t> bytes(v.size() * sizeof(T));
  if (!bytes.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
  return nlohmann::json::binary(std::move(bytes));
}

template <class T>
std::vector<T> vector_of(const nlohmann::json& j) {
  const std::vector<std::uint8_t>& bytes = j.get_binary();
  if (bytes.size() % sizeof(T) != 0)
    throw std::runtime_error(fmt::format("{} bytes are not whole values of {} bytes",
                                         bytes.size(), sizeof(T)));
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

nlohmann::json tile_json(const GalleryMember& g) {
  const DrawSurface& s = g.relaxed;
  return {{"surface", g.surface},
          {"name", g.name},
          {"alpha", g.alpha},
          {"mean_curvature", g.mean_curvature},
          {"positions", binary_of(s.positions)},
          {"normals", binary_of(s.normals)},
          {"curvature", binary_of(s.curvature)},
          {"triangles", binary_of(s.triangles)},
          {"lattice_cells", s.lattice_cells},
          {"origin", s.origin}};
}

GalleryMember tile_from_json(const nlohmann::json& j) {
  GalleryMember g;
  j.at("surface").get_to(g.surface);
  j.at("name").get_to(g.name);
  j.at("alpha").get_to(g.alpha);
  j.at("mean_curvature").get_to(g.mean_curvature);
  DrawSurface& s = g.relaxed;
  s.positions = vector_of<std::array<float, 3>>(j.at("positions"));
  s.normals = vector_of<std::array<float, 3>>(j.at("normals"));
  s.curvature = vector_of<float>(j.at("curvature"));
  s.triangles = vector_of<std::array<std::uint32_t, 3>>(j.at("triangles"));
  j.at("lattice_cells").get_to(s.lattice_cells);
  j.at("origin").get_to(s.origin);
  return g;
}

}  // namespace

std::vector<std::vector<int>> sweep_units(const SweepParams& params) {
  const int families = int(params.surfaces.size()), fractions = int(params.fractions.size());
  std::vector<std::vector<int>> units;
  for (int s = 0; s < families; ++s) {
    if (params.continuation) units.emplace_back();
    for (int f = 0; f < fractions; ++f) {
      if (!params.continuation) units.emplace_back();
      units.back().push_back(s * fractions + f);
    }
  }
  return units;
}

std::vector<int> assign_members(const SweepParams& params, int groups) {
  if (groups < 1) throw std::invalid_argument(fmt::format("assign_members: {} groups", groups));
  const std::vector<std::vector<int>> units = sweep_units(params);
  std::vector<int> order(units.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return units[a].size() > units[b].size(); });
  std::vector<std::size_t> load(std::size_t(groups), 0);
  std::vector<int> group(params.surfaces.size() * params.fractions.size(), 0);
  for (int u : order) {
    const int g = int(std::min_element(load.begin(), load.end()) - load.begin());  // first least
    load[std::size_t(g)] += units[std::size_t(u)].size();
    for (int m : units[std::size_t(u)]) group[std::size_t(m)] = g;
  }
  return group;
}

int default_groups(int ranks, int units, const std::function<bool(int group_ranks)>& splits) {
  std::vector<int> candidates;  // ascending
  for (int g = 1; g <= ranks; ++g)
    if (ranks % g == 0 && splits(ranks / g)) candidates.push_back(g);
  if (candidates.empty() || candidates.back() != ranks)
    throw std::logic_error("default_groups: groups of one process must split any grid");
  int largest = 0;
  for (int g : candidates)
    if (g <= units) largest = g;
  if (largest == 0) return candidates.front();  // more groups than units: some stay idle
  auto rounds = [&](int g) { return (units + g - 1) / g; };
  for (int g : candidates)
    if (rounds(g) == rounds(largest)) return g;
  return largest;
}

std::string group_grid_problem(const RunParams& p, int group_ranks) {
  if (group_ranks <= 1) return "";
  if (p.smoother != SweepOrder::kRedBlack)
    return "--smoother lex: a lexicographic Gauss-Seidel sweep depends on how the grid is "
           "split, so a member cannot run on several processes";
  if (const std::string why = Decomposition::check_grid_for(group_ranks, p.grid); !why.empty())
    return "--grid: " + why;
  for (int k = 1; k <= p.coarse_levels && check_coarsenable(p.grid >> k).empty(); ++k)
    if (const std::string why = Decomposition::check_grid_for(group_ranks, p.grid >> k);
        !why.empty())
      return fmt::format("--coarse-levels {}: the grid of level {}: {}", p.coarse_levels, k, why);
  return "";
}

std::string pack_group_rows(const GroupRows& g) {
  nlohmann::json rows = nlohmann::json::array();
  for (const GroupRows::Row& r : g.rows) {
    nlohmann::json row = {{"index", r.index}, {"report", r.report}};
    if (r.tile) row["tile"] = tile_json(*r.tile);
    rows.push_back(std::move(row));
  }
  const nlohmann::json j = {{"status", g.status},
                            {"message", g.message},
                            {"kept", g.kept},
                            {"resumed", g.resumed},
                            {"rows", std::move(rows)}};
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_msgpack(j);
  return std::string(bytes.begin(), bytes.end());
}

GroupRows unpack_group_rows(const std::string& bytes) {
  try {
    const nlohmann::json j = nlohmann::json::from_msgpack(bytes);
    GroupRows g;
    j.at("status").get_to(g.status);
    j.at("message").get_to(g.message);
    j.at("kept").get_to(g.kept);
    j.at("resumed").get_to(g.resumed);
    for (const nlohmann::json& row : j.at("rows")) {
      GroupRows::Row r;
      row.at("index").get_to(r.index);
      r.report = row.at("report");
      if (row.contains("tile")) r.tile = tile_from_json(row["tile"]);
      g.rows.push_back(std::move(r));
    }
    return g;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("a sweep group's rows are unreadable: {}", e.what()));
  }
}

}  // namespace cmcsurf
