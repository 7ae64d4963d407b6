#include "pipeline/member_topology.h"

#include <gtest/gtest.h>

namespace cmcsurf {
namespace {

// The families' topologies at alpha = 1/2 (docs/families.md): P -2, G -4, D -8.
TEST(MemberTopology, NodalStartsHaveTheFamiliesEulerCharacteristics) {
  EXPECT_EQ(nodal_start_euler_characteristic("P", 16), std::optional<std::int64_t>(-2));
  EXPECT_EQ(nodal_start_euler_characteristic("G", 16), std::optional<std::int64_t>(-4));
  EXPECT_EQ(nodal_start_euler_characteristic("D", 16), std::optional<std::int64_t>(-8));
  EXPECT_EQ(nodal_start_euler_characteristic("sphere", 16), std::nullopt);
}

TEST(MemberTopology, AChangedMemberIsRefusedNamingBoth) {
  // A report of an older cmcsurf (no euler_characteristic_start): the family's is computed.
  nlohmann::json r = {{"surface", "P"}, {"volume_fraction_target", 0.5}, {"grid", 16},
                      {"euler_characteristic", -2}};
  auto t = member_topology(r);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->family, -2);
  EXPECT_FALSE(t->changed());
  EXPECT_NO_THROW(check_member_topology(*t, "run", "--accept"));
  r["euler_characteristic"] = -1;
  r["euler_characteristic_start"] = -2;
  t = member_topology(r);
  ASSERT_TRUE(t && t->changed());
  try {
    check_member_topology(*t, "run", "--accept");
    ADD_FAILURE() << "not refused";
  } catch (const TopologyChangeError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("Euler characteristic -1"), std::string::npos) << m;
    EXPECT_NE(m.find("-2 (genus 3)"), std::string::npos) << m;
    EXPECT_NE(m.find("--accept"), std::string::npos) << m;
  }
  // No nodal target (a sphere run): nothing to compare.
  r["volume_fraction_target"] = nullptr;
  EXPECT_FALSE(member_topology(r));
}

}  // namespace
}  // namespace cmcsurf
