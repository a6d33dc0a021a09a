// The engines' real libraries as Debian installs them (engines/native/): each
// plugin that was built loads with the contract it states and answers
// hand-worked cases as its library does; a plugin that was not built is
// skipped, naming the package the manifest says is missing.
//
// The unit sphere at the origin, seen from o = (0, 0, -5) along +z: roots 4
// and 6 (the hit point (0, 0, -1)). Each engine's answer to a clear miss, an
// origin inside the sphere and a range that stops before the sphere follows
// from its contract (engines/native/README.md).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

const nlohmann::json& manifest() {
    static const nlohmann::json m = [] {
        std::ifstream in(RAYVERIFY_NATIVE_ENGINES_MANIFEST);
        if (!in) return nlohmann::json();
        return nlohmann::json::parse(in);
    }();
    return m;
}

const nlohmann::json* entry(const std::string& name) {
    for (const auto& e : manifest())
        if (e.at("name") == name) return &e;
    return nullptr;
}

// What each engine answers, per its contract; nullopt: a miss.
struct expectations {
    double tolerance;             // |t − expected| allowed (Bullet's GJK stops within about 1e-2)
    std::optional<double> front;  // o = (0,0,-5), range (0, +inf): the near root 4
    std::optional<double> inside; // o = (0,0,0.5): the far root 0.5, or a miss, or Irrlicht's line root
    std::optional<double> short_range;  // o = (0,0,-5), range (0, 3): the sphere is past its end
    bool any_hit;                 // answers yes/no only: t is not checked
};

const std::map<std::string, expectations>& expected() {
    static const std::map<std::string, expectations> e = {
        // [tnear, tfar], the far root from inside.
        {"embree3", {1e-5, 4.0, 0.5, std::nullopt, false}},
        {"embree3_robust", {1e-5, 4.0, 0.5, std::nullopt, false}},
        // The same call with one of Embree's kernels pinned.
        {"embree3_sse2", {1e-5, 4.0, 0.5, std::nullopt, false}},
        {"embree3_sse42", {1e-5, 4.0, 0.5, std::nullopt, false}},
        {"embree3_avx", {1e-5, 4.0, 0.5, std::nullopt, false}},
        {"embree3_avx2", {1e-5, 4.0, 0.5, std::nullopt, false}},
        {"embree3_avx512", {1e-5, 4.0, 0.5, std::nullopt, false}},
        // A segment; from inside the GJK cast reports nothing.
        {"bullet3", {2e-2, 4.0, std::nullopt, std::nullopt, false}},
        // [0, length], the exit from inside.
        {"ode", {1e-12, 4.0, 0.5, std::nullopt, false}},
        // The near root of the LINE, whatever its sign, and no range at all.
        {"irrlicht", {1e-5, 4.0, -1.5, 4.0, false}},
        // A yes/no on the segment's interior: a segment starting inside is a hit.
        {"openscenegraph", {0, 4.0, 0.0, std::nullopt, true}},
    };
    return e;
}

template <class T>
root_pair<T> ask(const variant& v, const ray_sphere<T>& s, T tmin, T tmax) {
    if constexpr (std::is_same_v<T, float>) {
        if (v.answer_float) return v.answer_float(s, tmin, tmax).roots;
        if (v.run_float_in) return v.run_float_in(s, tmin, tmax);
        return v.run_float(s);
    } else {
        if (v.answer_double) return v.answer_double(s, tmin, tmax).roots;
        if (v.run_double_in) return v.run_double_in(s, tmin, tmax);
        return v.run_double(s);
    }
}

template <class T>
void check(const variant& v, const expectations& e, const std::optional<double>& want, const ray_sphere<T>& s,
           T tmin, T tmax, const char* what) {
    const root_pair<T> r = ask(v, s, tmin, tmax);
    if (!want) {
        EXPECT_EQ(r.count, 0) << v.name << " " << what << ": a miss expected, got t = " << r.t0;
        return;
    }
    ASSERT_EQ(r.count, 1) << v.name << " " << what << ": a hit expected";
    if (!e.any_hit) {
        EXPECT_NEAR(static_cast<double>(r.t0), *want, e.tolerance) << v.name << " " << what;
    }
}

template <class T>
void hand_worked(const variant& v, const expectations& e) {
    const T big = std::numeric_limits<T>::infinity();
    const ray_sphere<T> front{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    check<T>(v, e, e.front, front, 0, big, "o = (0,0,-5) towards the unit sphere");
    // A direction of length 2: the same roots over 2 (an engine that assumes |d| = 1 would get 4).
    const ray_sphere<T> scaled{{0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1};
    std::optional<double> half = e.front;
    if (half) *half /= 2;
    check<T>(v, e, half, scaled, 0, big, "d = (0,0,2)");
    const ray_sphere<T> miss{{0, 5, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    check<T>(v, e, std::nullopt, miss, 0, big, "a clear miss (5 radii aside)");
    const ray_sphere<T> inside{{0, 0, T(0.5)}, {0, 0, 1}, {0, 0, 0}, 1};
    check<T>(v, e, e.inside, inside, 0, big, "origin inside");
    check<T>(v, e, e.short_range, front, 0, 3, "range (0, 3), the sphere at 4");
}

const char* const pinned_kernels[] = {"embree3_sse2", "embree3_sse42", "embree3_avx", "embree3_avx2", "embree3_avx512"};

// The target's plugin loaded, or why not: not built (the manifest's why_not),
// or a kernel this CPU does not run (the plugin's own reason).
std::optional<variant> loaded(const nlohmann::json& e, std::string& why_not) {
    if (e.at("plugin").is_null()) {
        why_not = e.at("why_not").get<std::string>();
        return std::nullopt;
    }
    try {
        return load_plugin(e.at("plugin").get<std::string>());
    } catch (const plugin_cannot_run_here& cannot) {
        why_not = cannot.what();
        return std::nullopt;
    }
}

class NativeEngine : public testing::TestWithParam<std::string> {};

TEST(NativeEngines, ManifestNamesEveryTargetWithItsPluginOrWhyNot) {
    ASSERT_TRUE(manifest().is_array()) << "no manifest at " << RAYVERIFY_NATIVE_ENGINES_MANIFEST;
    ASSERT_EQ(manifest().size(), expected().size());
    for (const auto& [name, unused] : expected()) {
        const nlohmann::json* e = entry(name);
        ASSERT_NE(e, nullptr) << name;
        EXPECT_FALSE(e->at("library").get<std::string>().empty());
        EXPECT_FALSE(e->at("package").get<std::string>().empty());
        if (e->at("plugin").is_null()) {
            EXPECT_NE(e->at("why_not").get<std::string>().find(e->at("package").get<std::string>()), std::string::npos);
        } else {
            EXPECT_TRUE(e->at("why_not").is_null());
            EXPECT_TRUE(std::filesystem::path(e->at("plugin").get<std::string>()).is_absolute());
        }
        // Embree's answers depend on the CPU (its kernel, its reciprocal estimate); the others' do not
        // (tools/cpu_dependence.sh reads their machine code).
        const bool embree = name.starts_with("embree3");
        EXPECT_EQ(e->at("depends_on_cpu").is_string(), embree) << name;
        const bool pinned = std::find(std::begin(pinned_kernels), std::end(pinned_kernels), name) != std::end(pinned_kernels);
        EXPECT_EQ(e->value("kernel_of", nlohmann::json()), pinned ? nlohmann::json("embree3") : nlohmann::json()) << name;
    }
}

// Embree 3 names the kernel it runs: its own choice for this CPU, or the one
// pinned; the pinned kernels are every kernel Debian's Embree has, each
// loaded as its own target beside the others, or unavailable here with the
// reason a CPU without it gives.
TEST(NativeEngines, EmbreeNamesTheKernelItRuns) {
    const nlohmann::json* embree = entry("embree3");
    ASSERT_NE(embree, nullptr);
    std::string why_not;
    const std::optional<variant> chosen = loaded(*embree, why_not);
    if (!chosen) GTEST_SKIP() << why_not;
    ASSERT_TRUE(chosen->library.has_value());
    EXPECT_TRUE(std::regex_match(chosen->library->configuration,
                                 std::regex("kernel (sse2|sse4\\.2|avx|avx2|avx512), Embree's choice for this CPU")))
        << chosen->library->configuration;
    std::size_t runnable = 0;
    for (const char* name : pinned_kernels) {
        const nlohmann::json* e = entry(name);
        ASSERT_NE(e, nullptr) << name;
        const std::optional<variant> pinned = loaded(*e, why_not);
        const std::string kernel = std::regex_replace(std::string(name).substr(8), std::regex("sse42"), "sse4.2");
        if (!pinned) {
            EXPECT_NE(why_not.find("this CPU does not run Embree's " + kernel + " kernel"), std::string::npos) << why_not;
            continue;
        }
        ++runnable;
        ASSERT_TRUE(pinned->library.has_value());
        EXPECT_EQ(pinned->library->configuration, "kernel " + kernel + ", pinned with isa=" + kernel);
    }
    EXPECT_GE(runnable, 1u) << "every x86-64 CPU runs the sse2 kernel";
    // The kernel Embree chose for this CPU is one of the pinned ones this CPU runs.
    const std::string kernel = std::regex_replace(chosen->library->configuration, std::regex("kernel (\\S+),.*"), "$1");
    EXPECT_NE(kernel, "unknown");
}

// The test hook makes the default target run another kernel, as on a CPU
// whose best kernel that is, and says so; a name that is no kernel makes it
// unavailable here, with the reason, and --engine with it an input error.
TEST(NativeEngines, EmbreeKernelTestHookRunsThatKernelAndSaysSo) {
    const nlohmann::json* embree = entry("embree3");
    ASSERT_NE(embree, nullptr);
    if (embree->at("plugin").is_null()) GTEST_SKIP() << embree->at("why_not").get<std::string>();
    const test_support::scratch_directory out("embree_kernel_hook");
    const std::string cases = (out.path() / "cases.jsonl").string();
    const test_support::command_result hooked = test_support::run_shell(
        "RAYVERIFY_TEST_EMBREE_KERNEL=sse2 " RAYVERIFY_CLI " audit --engine embree3 --engine embree3_sse2 --summary "
        "--per-case '" + cases + "'");
    ASSERT_EQ(hooked.exit_code, 1) << hooked.output;
    EXPECT_NE(hooked.output.find("library: embree3 is Embree 3 3.13.5 (Debian package libembree-dev), kernel sse2, set "
                                 "by RAYVERIFY_TEST_EMBREE_KERNEL"),
              std::string::npos)
        << hooked.output;
    // Every answer of the hooked default target is the pinned sse2 kernel's.
    std::ifstream lines(cases);
    std::size_t compared = 0;
    for (std::string line; std::getline(lines, line);) {
        const nlohmann::json c = nlohmann::json::parse(line);
        const nlohmann::json& results = c.at("results");
        ASSERT_TRUE(results.contains("embree3/float") && results.contains("embree3_sse2/float")) << line;
        const nlohmann::json &a = results["embree3/float"], &b = results["embree3_sse2/float"];
        for (const char* key : {"count", "t0", "t1"}) EXPECT_EQ(a.value(key, nlohmann::json()), b.value(key, nlohmann::json()))
            << c.at("id") << " " << key;
        ++compared;
    }
    EXPECT_EQ(compared, 3000u);

    const test_support::command_result listed =
        test_support::run_shell("RAYVERIFY_TEST_EMBREE_KERNEL=bogus " RAYVERIFY_CLI " engines");
    EXPECT_EQ(listed.exit_code, 0) << listed.output;
    EXPECT_TRUE(std::regex_search(listed.output, std::regex("\nembree3 .*not runnable here: "
                                                            "RAYVERIFY_TEST_EMBREE_KERNEL='bogus' names no Embree kernel")))
        << listed.output;
    const test_support::command_result refused =
        test_support::run_shell("RAYVERIFY_TEST_EMBREE_KERNEL=bogus " RAYVERIFY_CLI " audit --engine embree3");
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("engine library 'embree3' is not available on this machine"), std::string::npos)
        << refused.output;
}

// A gate baseline records the kernel Embree ran; the same gate with another
// kernel fails on the set-up, naming both, in the text and the JUnit file.
TEST(NativeEngines, GateRecordsEmbreesKernelAndFailsOnAnother) {
    const nlohmann::json* embree = entry("embree3");
    ASSERT_NE(embree, nullptr);
    std::string why_not;
    if (!loaded(*embree, why_not)) GTEST_SKIP() << why_not;
    const test_support::scratch_directory out("embree_gate");
    const std::string baseline = (out.path() / "baseline.txt").string();
    // Leak checking off for these runs: under load LeakSanitizer's tracer can crash while Embree's
    // TBB threads end (exit 1 after "gate: passed"); what is tested here is the gate.
    const std::string hook = "ASAN_OPTIONS=detect_leaks=0 RAYVERIFY_TEST_EMBREE_KERNEL=sse2 ";
    ASSERT_EQ(test_support::run_shell(hook + RAYVERIFY_CLI " gate --engine embree3 --baseline '" + baseline + "' --update")
                  .exit_code,
              0);
    EXPECT_NE(test_support::read_text(baseline).find("\nlibrary embree3 kernel sse2, set by RAYVERIFY_TEST_EMBREE_KERNEL"),
              std::string::npos);
    const test_support::command_result same =
        test_support::run_shell(hook + RAYVERIFY_CLI " gate --engine embree3 --baseline '" + baseline + "'");
    EXPECT_EQ(same.exit_code, 0) << same.output;
    const std::string junit = (out.path() / "gate.xml").string();
    const test_support::command_result other = test_support::run_shell(
        "ASAN_OPTIONS=detect_leaks=0 RAYVERIFY_TEST_EMBREE_KERNEL=avx " RAYVERIFY_CLI " gate --engine embree3 --baseline '" + baseline +
        "' --junit '" + junit + "'");
    EXPECT_EQ(other.exit_code, 1) << other.output;
    EXPECT_NE(other.output.find("SETUP  embree3: library set-up 'kernel sse2, set by RAYVERIFY_TEST_EMBREE_KERNEL"),
              std::string::npos)
        << other.output;
    EXPECT_NE(other.output.find("'kernel avx, set by RAYVERIFY_TEST_EMBREE_KERNEL"), std::string::npos) << other.output;
    EXPECT_NE(test_support::read_text(junit).find("<testcase classname=\"library set-up\" name=\"embree3\">"),
              std::string::npos);
}

// --engine NAME:kernels audits every pinned kernel this CPU runs, side by side.
TEST(NativeEngines, EveryKernelOfEmbreeAuditsSideBySide) {
    std::vector<std::string> runnable;
    for (const char* name : pinned_kernels) {
        const nlohmann::json* e = entry(name);
        ASSERT_NE(e, nullptr) << name;
        std::string why_not;
        if (loaded(*e, why_not)) runnable.push_back(name);
    }
    if (runnable.empty()) GTEST_SKIP() << "Embree 3 is not installed, or this CPU runs none of its kernels";
    const test_support::scratch_directory out("embree_kernels");
    const test_support::command_result ran = test_support::run_cli("audit --engine embree3:kernels --report '" +
                                                                   out.path().string() + "'");
    ASSERT_EQ(ran.exit_code, 1) << ran.output;
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(out.path() / "report.json"));
    std::vector<std::string> audited;
    for (const auto& r : report.at("results")) {
        audited.push_back(r.at("variant").get<std::string>());
        EXPECT_TRUE(r.at("library").at("configuration").get<std::string>().starts_with("kernel ")) << r.dump();
    }
    EXPECT_EQ(audited, runnable);
    const test_support::command_result unknown = test_support::run_cli("audit --engine bullet3:kernels");
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.output.find("engine library 'bullet3' has no pinned kernels"), std::string::npos) << unknown.output;
}

TEST_P(NativeEngine, AnswersHandWorkedCasesAsItsContractSays) {
    const nlohmann::json* e = entry(GetParam());
    ASSERT_NE(e, nullptr);
    std::string why_not;
    const std::optional<variant> plugin = loaded(*e, why_not);
    if (!plugin) GTEST_SKIP() << why_not;
    const variant& v = *plugin;
    EXPECT_EQ(v.name, GetParam()) << "the plugin's name is its target's";
    const expectations& want = expected().at(GetParam());
    ASSERT_TRUE(v.runs_in(precision::binary32) || v.runs_in(precision::binary64));
    if (v.runs_in(precision::binary32)) hand_worked<float>(v, want);
    if (v.runs_in(precision::binary64)) hand_worked<double>(v, want);
}

TEST_P(NativeEngine, ReportsTheLibraryVersionWhereTheLibraryHasOne) {
    const nlohmann::json* e = entry(GetParam());
    ASSERT_NE(e, nullptr);
    std::string why_not;
    if (!loaded(*e, why_not)) GTEST_SKIP() << why_not;
    void* library = dlopen(e->at("plugin").get<std::string>().c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    ASSERT_NE(library, nullptr) << dlerror();
    auto version = reinterpret_cast<const char* (*)()>(dlsym(library, "rayverify_plugin_library_version"));
    ASSERT_NE(version, nullptr) << "every native plugin exports rayverify_plugin_library_version";
    const char* reported = version();
    if (GetParam() == "ode") {
        EXPECT_EQ(reported, nullptr) << "ODE has no version call: NULL, for the package's version";
    } else {
        ASSERT_NE(reported, nullptr);
        EXPECT_TRUE(std::regex_match(reported, std::regex(R"(\d+\.\d+(\.\d+)?)"))) << reported;
    }
    dlclose(library);
}

INSTANTIATE_TEST_SUITE_P(Targets, NativeEngine,
                         testing::Values("embree3", "embree3_robust", "embree3_sse2", "embree3_sse42", "embree3_avx",
                                         "embree3_avx2", "embree3_avx512", "bullet3", "ode", "irrlicht",
                                         "openscenegraph"),
                         [](const testing::TestParamInfo<std::string>& info) { return info.param; });

// Inputs a library refuses by stopping the program (Debian builds Embree and
// ODE with their assertions on) come back unanswered (count -1, judged
// malformed_output) instead of taking the audit down.
TEST(NativeEngines, InputsTheLibraryRefusesComeBackUnanswered) {
    const nlohmann::json* embree = entry("embree3");
    ASSERT_NE(embree, nullptr);
    if (!embree->at("plugin").is_null()) {
        const variant v = load_plugin(embree->at("plugin").get<std::string>());
        // |d| beyond Embree's FLT_LARGE (1.844e18): rtcIntersect1 would assert ray.valid().
        const ray_sphere<float> huge{{0, 0, -5}, {0, 0, 1e19f}, {0, 0, 0}, 1};
        EXPECT_EQ(ask<float>(v, huge, 0, std::numeric_limits<float>::infinity()).count, -1);
        const ray_sphere<float> fine{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
        EXPECT_EQ(ask<float>(v, fine, 0, std::numeric_limits<float>::infinity()).count, 1) << "and the next case runs";
    }
    const nlohmann::json* ode = entry("ode");
    ASSERT_NE(ode, nullptr);
    if (!ode->at("plugin").is_null()) {
        const variant v = load_plugin(ode->at("plugin").get<std::string>());
        // dGeomRaySet cannot normalize a zero direction: ODE's internal assertion.
        const ray_sphere<double> zero{{0, 0, -5}, {0, 0, 0}, {0, 0, 0}, 1};
        EXPECT_EQ(ask<double>(v, zero, 0, inf).count, -1);
        const ray_sphere<double> fine{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
        const root_pair<double> r = ask<double>(v, fine, 0, inf);
        EXPECT_EQ(r.count, 1) << "and the next case runs";
        EXPECT_NEAR(r.t0, 4.0, 1e-12);
    }
}

// Every built plugin through the CLI on corpus/edge, in one audit: no library
// takes the audit down, and the rays Embree refuses (|org| or |dir| beyond
// FLT_LARGE, tnear < 0) and the cases ODE stops on (near the double overflow threshold)
// are exactly the unanswered ones.
TEST(NativeEngines, EveryBuiltPluginAuditsTheEdgeCorpus) {
    std::string plugins;
    std::map<std::string, bool> built;
    for (const auto& e : manifest()) {
        std::string why_not;
        if (!loaded(e, why_not)) continue;  // not built, or a kernel this CPU does not run
        plugins += " --plugin '" + e.at("plugin").get<std::string>() + "'";
        built[e.at("name").get<std::string>()] = true;
    }
    if (built.empty()) GTEST_SKIP() << "no engine package was found when rayverify was built";
    const test_support::scratch_directory out("native_engines_edge");
    const test_support::command_result ran = test_support::run_cli(
        "audit" + plugins + " --corpus " RAYVERIFY_CORPUS_DIR "/edge --report '" + out.path().string() + "'");
    ASSERT_EQ(ran.exit_code, 1) << "findings, no error:\n" << ran.output;
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(out.path() / "report.json"));
    std::map<std::string, int> malformed;
    for (const auto& r : report.at("results")) {
        const std::string name = r.at("variant").get<std::string>();
        EXPECT_TRUE(built.count(name)) << name;
        malformed[name] += r.at("verdicts").at("malformed_output").get<int>();
    }
    EXPECT_EQ(malformed.size(), built.size());
    // Embree's traversal asserts tnear >= 0: the range-end families' intervals that start behind the origin.
    int negative_tnear = 0;
    for (const corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR "/edge"}))
        negative_tnear += c.tmin && static_cast<float>(*c.tmin) < 0.0f;
    EXPECT_GT(negative_tnear, 0);
    for (const auto& [name, unused] : built) {
        if (name.starts_with("embree3")) {
            EXPECT_EQ(malformed[name], 403 + negative_tnear)
                << name << ": near_overflow_f32 300, scaled_direction 44, scaled_direction_f32 59, and the casts "
                << "starting behind the origin";
        }
    }
    if (built.count("ode")) {
        EXPECT_EQ(malformed["ode"], 300) << "near_overflow";
    }
    for (const char* name : {"bullet3", "irrlicht", "openscenegraph"}) {
        if (built.count(name)) {
            EXPECT_EQ(malformed[name], 0) << name;
        }
    }
}

}  // namespace
}  // namespace rayverify
