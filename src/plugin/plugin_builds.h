// Plugins built from a user's source under several compilers and flag sets,
// as `rayverify builds` runs it (docs/builds.md): which compilers this machine
// has, a build's name and flags, the flags refused, the plugins compiled (two
// at a time, cached by the content of everything they were built from), the
// components a build's flags break into for the bisect, and the
// delta-debugging search for the smallest set of them that reproduces a
// change.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace rayverify {

// A compiler of the matrix, by the name its builds carry: `gcc` (Debian's
// gcc 12, gcc/g++) or `clang` (Debian's clang 14, clang-14/clang++-14 or
// clang/clang++).
struct compiler_driver {
    std::string name;         // "gcc", "clang"
    std::string c_command;    // the command that compiles C, found on PATH
    std::string cxx_command;  // and C++
    std::string version;      // the first line of `c_command --version`
};

// The compiler named `name` as this machine has it; nullopt when it has none
// of its commands. Throws input_error for a name that is neither gcc nor clang.
std::optional<compiler_driver> find_compiler(const std::string& name);

// The flags of the reference build, against which every other build's answers
// are compared (with gcc: docs/builds.md).
inline constexpr const char* reference_flags_text = "-O2 -ffp-contract=off -fno-fast-math";

// The default matrix's flag sets, for each compiler.
std::vector<std::string> default_flag_sets();

// One build of the matrix.
struct build_spec {
    std::string name;  // the build's target name: "gcc-O2-ffast-math"
    compiler_driver compiler;
    std::vector<std::string> flags;  // one word each, as given
    // The bisect's component "FTZ/DAZ at load": an object whose constructor
    // sets them is linked in, as a -ffast-math link's crtfastmath.o does.
    bool ftz_daz_at_load = false;
    bool reference = false;
};

// `text` split into words at white space (no quoting: a flag holds none).
std::vector<std::string> flag_words(const std::string& text);
// "gcc-O2-ffast-math": the compiler's name and each flag, joined by '-' with
// their leading dashes dropped; a target name (no space, '/' or '#').
std::string build_name(const std::string& compiler, std::span<const std::string> flags);
// Throws input_error (field `option`) for a flag that injects code or
// changes what is built rather than how it is compiled: -include, -imacros,
// -fplugin, -specs, -B, -wrapper, @file, -o, -c, -E, -S, -x, -Wl/-Xlinker
// and the like (docs/builds.md says why each is refused).
void check_build_flags(std::span<const std::string> flags, const std::string& option);

// A source's language by its extension: C (.c) or C++ (.cc, .cpp, .cxx,
// .c++, .C); nullopt for any other.
enum class source_language { c, cxx };
std::optional<source_language> language_of(const std::filesystem::path& source);

// What `builds` compiles: the sources under each build's flags, the harness
// (the plugin's glue, which should not change with the build) under the
// reference flags in every build, with the include directories and defines.
struct build_sources {
    std::vector<std::filesystem::path> sources, harness;
    std::vector<std::string> include_dirs, defines;
    // The language standards every compile of a C / C++ source names
    // (-std=...; empty: the compiler's default, gnu17 / gnu++17 for gcc 12
    // but gnu++14 for clang 14).
    std::string c_standard, cxx_standard;
    // Libraries the plugin links (-lNAME after its objects): an engine
    // adapter's library as installed, whose own code no build changes.
    std::vector<std::string> libraries;
};

// A build as it came out.
struct built_plugin {
    build_spec spec;
    std::vector<std::string> command_lines;  // every compile and the link, as run (or as cached)
    std::filesystem::path plugin;            // empty when it did not build
    std::string failure;                     // the compiler's first error line, when it did not
    bool refused_by_source = false;          // it did not because an #error of the source's stopped it
    bool cached = false;                     // taken from the cache, not compiled now
    bool built() const { return !plugin.empty(); }
};

// Builds every spec into a plugin under `cache_dir` (created when missing),
// `jobs` builds at a time. A build is reused when the compiler's version and
// commands, the flags, the include directories and defines, and the content of
// every file its last compile read (sources, harness and every header, from
// the compiler's dependency list) are those it was built from. A build that
// does not compile (or takes more than 300 s) comes back with its failure;
// the others are built.
std::vector<built_plugin> build_plugins(std::span<const build_spec> specs, const build_sources& sources,
                                        const std::filesystem::path& cache_dir, unsigned jobs = 2);

// The default cache: $XDG_CACHE_HOME/rayverify/builds, else ~/.cache/rayverify/builds.
std::filesystem::path default_build_cache();

// A build's flags broken into the components the bisect removes one set at a
// time: each of its own flags, with -ffast-math and -Ofast expanded into what
// they switch on (GCC's and clang's manuals, and clang's -### for its own:
// -fno-math-errno, -ffinite-math-only, -fno-signed-zeros, -fno-trapping-math,
// -fassociative-math, -freciprocal-math, -ffp-contract=fast, __FAST_MATH__
// defined; with gcc -fcx-limited-range; with clang -fapprox-func and
// -fdenormal-fp-math=preserve-sign; -Ofast also -O3 and, with gcc,
// -fallow-store-data-races), and FTZ/DAZ at load when the build's library
// set them (`loads_with_ftz_daz`, as measured when it was loaded).
struct flag_component {
    std::string label;               // as printed: "-ffinite-math-only", "FTZ/DAZ at load"
    std::vector<std::string> flags;  // what it adds to a build's flags
    bool ftz_daz_at_load = false;
};
std::vector<flag_component> flag_components(const build_spec& build, bool loads_with_ftz_daz);
// The build of `components` alone (in their order) with `build`'s compiler.
build_spec build_of_components(const build_spec& build, std::span<const flag_component> components);

// Zeller and Hildebrandt's ddmin ("Simplifying and isolating failure-inducing
// input", 2002) over the indices 0..n−1: a subset for which `reproduces`
// holds from which no single index can be removed (1-minimal), given that the
// whole set reproduces. `reproduces` is asked of each subset at most once.
std::vector<std::size_t> smallest_reproducing_subset(
    std::size_t n, const std::function<bool(const std::vector<std::size_t>&)>& reproduces);

}  // namespace rayverify
