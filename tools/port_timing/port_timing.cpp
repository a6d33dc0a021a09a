// Every engine port (src/intersectors/) and naive timed as this file is
// compiled. CMakeLists.txt builds it twice: port_timing_rayverify with the
// flags rayverify compiles the ports with (-O2, the SLP vectoriser off, as
// the library and `rayverify bench` run them), and port_timing_release as an
// engine's own CMake Release build compiles the same code (-O3, the
// vectoriser on; no -march: on x86-64 no FMA instruction for a compiler to
// contract into, so the answers are the same, which each line's checksum
// shows). tools/port_build_benchmark.sh runs both and prints each port's
// cost in both builds: what of a port's time is the compiler's, and what is
// its engine's own arithmetic. Two executables, not two translation units of
// one: the ports are inline templates, and a linker keeps one copy of each.
//
// Usage: port_timing [--list] [--cases N] [--seconds S]
//   --list     the ports' names, one a line (a test checks them against the registry)
//   otherwise  one line per port and precision: name precision ns_per_test checksum,
//              the median of 5 timed passes over N cases (default 4096) of at least S
//              seconds each (default 0.2), one thread
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/float_bits.h"
#include "intersectors/all.h"

namespace {

using namespace rayverify;

template <class T>
root_pair<T> roots_of(const root_pair<T>& r) {
    return r;
}
template <class T>
root_pair<T> roots_of(const answer<T>& a) {
    return a.roots;
}

// A port as the registry binds it: (s, tmin, tmax) on [0, +inf), its roots.
template <class T>
using port_fn = root_pair<T> (*)(const ray_sphere<T>&);

template <class T, auto F>
root_pair<T> on_ray(const ray_sphere<T>& s) {
    return roots_of(F(s, T(0), std::numeric_limits<T>::infinity()));
}

struct port {
    const char* name;
    port_fn<float> in_float;    // nullptr: the engine has no float build
    port_fn<double> in_double;  // nullptr: no double build
};

// The ports of src/intersectors/variants.def, in its order.
#define RAYVERIFY_IN_yes(fn, T) on_ray<T, intersectors::fn<T>>
#define RAYVERIFY_IN_no(fn, T) nullptr
const port ports[] = {
#define RAYVERIFY_PORT(fn, in_float, in_double, citation, formula, build) \
    {#fn, RAYVERIFY_IN_##in_float(fn, float), RAYVERIFY_IN_##in_double(fn, double)},
#include "intersectors/variants.def"
};
#undef RAYVERIFY_IN_no
#undef RAYVERIFY_IN_yes

// Rays from a box of side 20 around spheres near the origin, aimed at the
// centre within half a radius or so: hits, misses and grazes, as `uniform`.
template <class T>
std::vector<ray_sphere<T>> cases_in(std::size_t count) {
    std::mt19937_64 random(20261127);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::vector<ray_sphere<T>> cases;
    for (std::size_t i = 0; i < count; ++i) {
        const vec3<double> o{10 * unit(random), 10 * unit(random), 10 * unit(random)};
        const vec3<double> c{unit(random), unit(random), unit(random)};
        const vec3<double> d{c.x - o.x + unit(random), c.y - o.y + unit(random), c.z - o.z + unit(random)};
        const double r = 1 + 0.5 * unit(random);
        cases.push_back({{T(o.x), T(o.y), T(o.z)}, {T(d.x), T(d.y), T(d.z)}, {T(c.x), T(c.y), T(c.z)}, T(r)});
    }
    return cases;
}

// The answers' bits folded together: the same in both builds when the answers are.
template <class T>
std::uint64_t checksum_of(const std::vector<ray_sphere<T>>& cases, port_fn<T> fn) {
    std::uint64_t sum = 0;
    for (const ray_sphere<T>& s : cases) {
        const root_pair<T> r = fn(s);
        const std::uint64_t t0 = std::bit_cast<float_bits_t<T>>(r.t0), t1 = std::bit_cast<float_bits_t<T>>(r.t1);
        const std::uint64_t bits = (t0 * 3 + t1) * 5 + static_cast<std::uint64_t>(r.count);
        sum = (sum ^ bits) * 0x100000001B3ull;
    }
    return sum;
}

template <class T>
double ns_per_test(const std::vector<ray_sphere<T>>& cases, port_fn<T> fn, double seconds) {
    std::vector<double> passes;
    volatile T sink = 0;
    for (int pass = 0; pass < 5; ++pass) {
        std::size_t tests = 0;
        const auto start = std::chrono::steady_clock::now();
        double elapsed = 0;
        do {
            T sum = 0;
            for (const ray_sphere<T>& s : cases) sum += fn(s).t0;
            sink = sink + sum;
            tests += cases.size();
            elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        } while (elapsed < seconds);
        passes.push_back(elapsed * 1e9 / static_cast<double>(tests));
    }
    std::sort(passes.begin(), passes.end());
    return passes[passes.size() / 2];
}

template <class T>
void time_port(const char* name, const char* precision, const std::vector<ray_sphere<T>>& cases, port_fn<T> fn,
               double seconds) {
    if (fn == nullptr) return;
    std::printf("%s %s %.2f %016llx\n", name, precision, ns_per_test(cases, fn, seconds),
                static_cast<unsigned long long>(checksum_of(cases, fn)));
}

[[noreturn]] void usage(const char* why) {
    std::fprintf(stderr, "port_timing: %s\nusage: port_timing [--list] [--cases N] [--seconds S]\n", why);
    std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t count = 4096;
    double seconds = 0.2;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--list") {
            for (const port& p : ports) std::printf("%s\n", p.name);
            return 0;
        }
        if (i + 1 >= argc) usage(("missing a value after " + arg).c_str());
        char* end = nullptr;
        if (arg == "--cases") {
            count = std::strtoull(argv[++i], &end, 10);
            if (*end != '\0' || count == 0 || count > 10'000'000) usage("--cases: a whole number from 1 to 10000000");
        } else if (arg == "--seconds") {
            seconds = std::strtod(argv[++i], &end);
            if (*end != '\0' || !(seconds > 0 && seconds <= 60)) usage("--seconds: a number > 0 and ≤ 60");
        } else {
            usage(("unknown option " + arg).c_str());
        }
    }
    const std::vector<ray_sphere<float>> in_float = cases_in<float>(count);
    const std::vector<ray_sphere<double>> in_double = cases_in<double>(count);
    time_port("naive", "double", in_double, port_fn<double>{[](const ray_sphere<double>& s) { return intersectors::naive(s); }},
              seconds);
    for (const port& p : ports) {
        time_port(p.name, "float", in_float, p.in_float, seconds);
        time_port(p.name, "double", in_double, p.in_double, seconds);
    }
    return 0;
}
