// The engines' libraries rayverify audits as their packages install them
// (`rayverify engines`, `--engine NAME`; docs/engines.md):
// - C and C++ libraries from Debian packages, each called through a plugin
//   (engines/native/) that CMake builds beside rayverify when it finds the
//   package; the build lists every one, built or not and why, in
//   engines/native_engines.json;
// - JavaScript libraries from npm, pinned by engines/js/package-lock.json and
//   installed by `npm ci`, each called by a node program (engines/js/) that
//   answers batches of cases through the results protocol on its standard
//   input and output (corpus/external_program.h); engines/js/engines.json
//   lists them.
// A library's version is the one it reports itself where it can
// (rayverify_plugin_library_version, the npm package's package.json), else
// the package manager's.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"

namespace rayverify::cli {

struct shipped_library {
    enum class runner { plugin, program };

    std::string name;            // the target's name: --engine NAME, reports, baselines
    library_identity identity;   // the library's own name, its version here, its package
    runner how = runner::plugin;
    std::filesystem::path plugin;  // runner::plugin: the plugin built for it
    std::string command;           // runner::program: the command line (/bin/sh -c) of its adapter
    // The precisions it computes in and its contract spec: a program's from
    // its manifest, a plugin's from the plugin itself (empty when it is not
    // available and could not be asked).
    std::vector<precision> precisions;
    std::string contract;
    std::string api;      // the call made, e.g. "rtcIntersect1"; may be empty
    std::string why_not;  // empty when it can be audited here; else why not, and how to install it
    // why_not is this machine's: the library is installed, but says it cannot
    // run here (a kernel this CPU lacks); not a broken or missing install.
    bool runs_elsewhere_only = false;
    // Why its answers depend on the CPU it runs on (an ISA dispatch, the CPU's
    // reciprocal estimate); empty when they do not.
    std::string depends_on_cpu;
    // The target whose kernel this one pins (e.g. "embree3" for
    // "embree3_sse2"); empty for a target as the library runs itself.
    std::string kernel_of;

    bool available() const { return why_not.empty(); }
};

// Every library rayverify knows, available here or not, in a fixed order
// (Debian packages first, then npm packages; each group by name). Found once
// per process (it loads every plugin and asks node and dpkg): later calls
// return the same list.
const std::vector<shipped_library>& shipped_libraries();

// The library named `name`, available here. Throws input_error (field
// "--engine") for an unknown name (listing the known ones) or one that is not
// available (saying why and how to install it, or that this machine cannot
// run it).
shipped_library available_library(const std::string& name);

// What `--engine` names, in order: each name as available_library finds it,
// and `NAME:kernels` as every target pinning one of NAME's kernels that runs
// on this machine (embree3:kernels: embree3_sse2 ... embree3_avx512), lowest
// kernel first. Throws input_error (field "--engine") as available_library
// does, and for `NAME:kernels` when NAME has no pinned kernels, or none of
// them runs here.
std::vector<shipped_library> requested_libraries(const std::vector<std::string>& names);

// The suffix of `--engine NAME:kernels`.
inline constexpr std::string_view every_kernel_suffix = ":kernels";

}  // namespace rayverify::cli
