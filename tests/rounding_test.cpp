// Rounding a case's inputs to float and back must round every field. g++ 12.2
// at -O2 with the SLP vectorizer skips the rounding of some fields of this
// exact expression (the project builds with -fno-tree-slp-vectorize for that
// reason); this test fails if the flag is ever dropped.
#include <gtest/gtest.h>

#include "core/ray_sphere_case.h"

namespace rayverify {
namespace {

[[gnu::noinline]] ray_sphere<double> through_float(const ray_sphere<double>& s) {
    return rounded_to<double>(rounded_to<float>(s));
}

double through_float(double x) { return static_cast<double>(static_cast<float>(x)); }

TEST(Rounding, EveryFieldOfACaseIsRoundedToFloat) {
    // Values with more than 24 significant bits, chosen at run time so the
    // compiler cannot fold them.
    volatile double k = 1;
    const ray_sphere<double> s{{k / 3, k / 7, k / 11}, {k / 13, k / 17, k / 19}, {k / 23, k / 29, k / 31}, k / 37};
    const ray_sphere<double> r = through_float(s);
    for (int axis = 0; axis < 3; ++axis) {
        SCOPED_TRACE(axis);
        EXPECT_EQ(r.origin[axis], through_float(s.origin[axis]));
        EXPECT_EQ(r.direction[axis], through_float(s.direction[axis]));
        EXPECT_EQ(r.centre[axis], through_float(s.centre[axis]));
    }
    EXPECT_EQ(r.radius, through_float(s.radius));
}

}  // namespace
}  // namespace rayverify
