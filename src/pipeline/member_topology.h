// Whether a computed member has its family's topology. Near a family's topology
// change a run can end on a member of another one (P at porosity 0.75: perforated plates,
// genus 2; at 0.8 separate balls) that a scaffold would then print in place of the lattice
// asked for. The family's topology is that of the nodal start phi^0 = F + 1/2 (step 1's field,
// e.g. P genus 3, G 5, D 9), both as measure/topology.h's Euler characteristic of phase 1; a
// run reports both (report.json euler_characteristic, euler_characteristic_start).
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>


namespace cmcsurf {

// chi of phase 1 of the nodal start of `surface` on an n^3 grid; nullopt for a surface
// without a nodal formula.
std::optional<std::int64_t> nodal_start_euler_characteristic(const std::string& surface, int n);

struct MemberTopology {
  std::string surface;
  double volume_fraction = 0.0;  // the target
  std::int64_t member = 0;       // the run's euler_characteristic
  std::int64_t family = 0;       // euler_characteristic_start
  bool changed() const { return member != family; }
};

// From a run's report (report.json, or a scaffold cache's member.json "run"): the member's chi
// and its family's (euler_characteristic_start; computed from the surface and grid when the
// report lacks it: written by an older cmcsurf, or a sweep member continued from a neighbour).
// nullopt when the report says neither (no nodal target, or no sharp measures).
std::optional<MemberTopology> member_topology(const nlohmann::json& run_report);

// A member of another topology than its family's, refused by scaffold, mesh and Python's mesh.
struct TopologyChangeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws TopologyChangeError when t changed, naming both Euler characteristics, `what` (the
// member's file or folder) and `accept` (the option that takes the member anyway).
void check_member_topology(const MemberTopology& t, const std::string& what,
                           const std::string& accept);

}  // namespace cmcsurf
