// The registry of floating-point intersectors: every variant with its name,
// source, formula and contract, callable in float and in double. The CLI,
// tests and benchmarks iterate over it instead of naming variants.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

struct variant {
    std::string name;      // stable identifier used on the command line and in reports
    std::string citation;  // where the formula comes from
    std::string formula;   // one line, in the paper's notation
    contract promises;
    // Empty when the variant does not run in that precision. A std::function
    // so that a variant can carry state (a plugin's loaded symbol, a mutant).
    std::function<root_pair<float>(const ray_sphere<float>&)> run_float;
    std::function<root_pair<double>(const ray_sphere<double>&)> run_double;

    bool runs_in(precision p) const {
        return p == precision::binary32 ? static_cast<bool>(run_float) : static_cast<bool>(run_double);
    }
};

// All built-in variants, in a fixed order (the order of reports).
std::span<const variant> builtin_variants();

// nullptr when no built-in variant has that name.
const variant* find_builtin_variant(std::string_view name);

}  // namespace rayverify
