// The registry of floating-point intersectors: every variant with its name,
// source, formula and contract, callable in float and in double. The CLI,
// tests and benchmarks iterate over it instead of naming variants.
#pragma once

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
    root_pair<float> (*run_float)(const ray_sphere<float>&) = nullptr;
    root_pair<double> (*run_double)(const ray_sphere<double>&) = nullptr;

    bool runs_in(precision p) const {
        return p == precision::binary32 ? run_float != nullptr : run_double != nullptr;
    }
};

// All built-in variants, in a fixed order (the order of reports).
std::span<const variant> builtin_variants();

// nullptr when no built-in variant has that name.
const variant* find_builtin_variant(std::string_view name);

}  // namespace rayverify
