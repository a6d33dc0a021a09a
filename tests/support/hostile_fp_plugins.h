// Plugins that change the floating-point environment, loaded into a test's
// own process before a long sweep of the oracle or the judge: the sweep must
// hold with them loaded (core/fp_environment.h). Needs the fixture paths
// RAYVERIFY_FIXTURE_FP_HOSTILE and RAYVERIFY_FIXTURE_FP_FAST_MATH_LINK
// (tests/CMakeLists.txt).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>
#include <vector>

#include "core/fp_environment.h"
#include "plugin/plugin_loader.h"

namespace rayverify::test_support {

// Loads a plugin linked with -ffast-math (FTZ+DAZ at load) and one that traps
// FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW after every batch, calls each once
// on this thread, and checks that this thread is in the IEEE default after.
inline std::vector<variant> load_hostile_fp_plugins() {
    ::setenv("FIXTURE_FP_MODE", "batch_unmask", 1);
    std::vector<variant> loaded = {load_plugin(RAYVERIFY_FIXTURE_FP_HOSTILE), load_plugin(RAYVERIFY_FIXTURE_FP_FAST_MATH_LINK)};
    ::unsetenv("FIXTURE_FP_MODE");
    const ray_sphere<double> s{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    for (const variant& v : loaded) {
        EXPECT_EQ(v.run_double(s).count, 2) << v.name;
        EXPECT_TRUE(is_ieee_default(current_fp_state())) << v.name << " left " << describe_fp_state(current_fp_state());
    }
    EXPECT_FALSE(loaded[1].fp_environment.empty()) << "the -ffast-math link set FTZ+DAZ when it loaded";
    return loaded;
}

}  // namespace rayverify::test_support
