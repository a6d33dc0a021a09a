// Internal to plugin/: a plugin library opened and checked in the process
// that calls it, and the variant it describes. Shared by load_plugin (in this
// process) and the child process of an isolated plugin (plugin_host).
#pragma once

#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "intersectors/registry.h"
#include "plugin/rayverify_plugin.h"

namespace rayverify::plugin_internal {

// What describe() says, checked, its texts copied (NULL ones replaced by
// their defaults), and whether the library has a float function.
struct plugin_description {
    std::string name, citation, formula, tangent_rule;
    int query = RAYVERIFY_LINE_ROOTS;
    bool assumes_unit_direction = false, reports_tangent = false, clamps_to_zero = false;
    bool has_float = false;
};

struct opened_library {
    std::shared_ptr<void> handle;  // dlclose when the last copy goes
    rayverify_intersect_double_fn run_double = nullptr;
    rayverify_intersect_float_fn run_float = nullptr;  // nullptr when the library has none
    plugin_description description;
};

// Why a library cannot be used: the text after "LIBRARY: field '--plugin': ".
class unusable_library : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// dlopen the library and check what it describes. Throws unusable_library
// (missing file or symbol, not loadable, another ABI version, no name, a name
// that is not one token, an unknown query kind).
opened_library open_library(const std::filesystem::path& library);

// The variant the description stands for: name, citation, formula and
// contract; no run functions, thread_safe false (the ABI calls from one thread).
variant described_variant(const plugin_description& description);

// The interval a plain run function passes as (tmin, tmax): the one its
// contract is judged on.
template <class T>
T interval_start(const contract& promises) {
    return promises.query == query_kind::line_roots ? -std::numeric_limits<T>::infinity() : T(0);
}

}  // namespace rayverify::plugin_internal
