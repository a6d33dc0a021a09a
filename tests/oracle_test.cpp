#include <gtest/gtest.h>
#include "oracle/oracle.h"
using namespace rayverify;
TEST(Oracle, Smoke) {
    ray_sphere<double> s{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    auto sol = solve_exact(s, precision::binary64);
    EXPECT_EQ(sol.cls, line_class::two_hit);
    EXPECT_EQ(sol.near_root.rounded, 4.0);
    EXPECT_EQ(sol.far_root.rounded, 6.0);
}
