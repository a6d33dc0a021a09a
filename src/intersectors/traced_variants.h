// Every built-in variant's own intersector run on traced scalars
// (intersectors/traced.h), for `explain`: the steps it names, each computed
// as the plain float or double instantiation computes it and beside the
// ideal value of the same expression. Kept apart from registry.cpp so that
// the traced instantiations compile in a file of their own and the audited
// functions stay as they are.
#pragma once

#include <string_view>

#include "core/ray_sphere_case.h"

namespace rayverify {

// Runs the variant on (tmin, tmax) (ignored by a kind that takes no
// interval), recording its steps and then its roots into the thread's
// trace_session.
template <class T>
using trace_fn = void (*)(const ray_sphere<T>& s, T tmin, T tmax);

struct variant_trace {
    std::string_view name;        // the registry's name
    trace_fn<float> in_float;     // nullptr when the variant has no float build
    trace_fn<double> in_double;   // nullptr when it has no double build
    std::string_view what;        // what the steps are when not the formula's own code run traced; else empty
};

// nullptr when no built-in variant has that name.
const variant_trace* find_builtin_trace(std::string_view name);

}  // namespace rayverify
