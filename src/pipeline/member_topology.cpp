#include "pipeline/member_topology.h"

#include <fmt/format.h>

#include "measure/topology.h"
#include "surfaces/initial.h"

namespace cmcsurf {

std::optional<std::int64_t> nodal_start_euler_characteristic(const std::string& surface,
                                                             int n) {
  if (!is_nodal_surface(surface)) return std::nullopt;
  InitialFieldParams init;
  init.surface = surface;
  return euler_characteristic(make_initial_field(init, n, 2));
}

std::optional<MemberTopology> member_topology(const nlohmann::json& r) {
  if (!r.is_object() || !r.contains("euler_characteristic") ||
      !r["euler_characteristic"].is_number_integer() || !r.contains("surface") ||
      !r["surface"].is_string() || !r.contains("volume_fraction_target") ||
      !r["volume_fraction_target"].is_number() || !r.contains("grid") ||
      !r["grid"].is_number_integer())
    return std::nullopt;
  MemberTopology t;
  t.surface = r["surface"].get<std::string>();
  t.volume_fraction = r["volume_fraction_target"].get<double>();
  t.member = r["euler_characteristic"].get<std::int64_t>();
  if (r.contains("euler_characteristic_start") &&
      r["euler_characteristic_start"].is_number_integer()) {
    t.family = r["euler_characteristic_start"].get<std::int64_t>();
    return t;
  }
  const auto family = nodal_start_euler_characteristic(t.surface, r["grid"].get<int>());
  if (!family) return std::nullopt;
  t.family = *family;
  return t;
}

void check_member_topology(const MemberTopology& t, const std::string& what,
                           const std::string& accept) {
  if (!t.changed()) return;
  throw TopologyChangeError(fmt::format(
      "{}: the {} member at solid fraction {:g} has Euler characteristic {} (genus {}), its "
      "family's (the nodal {} the run starts from) {} (genus {}): the run ended on a member of "
      "another topology (near a topology change of the family, e.g. P's channels pinching "
      "off into plates or balls), not the lattice asked for, so nothing was written. Choose a "
      "solid fraction (1 - porosity) closer to 1/2, another --surface or other run options "
      "(--grid, --fast, --epsilon), or {} to use this member anyway",
      what, t.surface, t.volume_fraction, t.member, 1 - t.member, t.surface, t.family,
      1 - t.family, accept));
}

}  // namespace cmcsurf
