// A consumer built with the compiler's default flags plus -mfma, which would
// contract a*b + c into an FMA: the header intersectors it instantiates must
// give, bit for bit, the answers of the same variants compiled into the
// library (what the audit measured). The FP flags reach it as usage
// requirements of rayverify::rayverify.
//
//   consumer_flags               exit 0 when every answer matches
//   consumer_flags --unguarded   exit 0 when some answer differs: built without
//                                the usage requirements, this proves the check
//                                can fail (the cases are sensitive to contraction)
#include <rayverify/intersectors/half_b.h>
#include <rayverify/intersectors/naive.h>
#include <rayverify/intersectors/registry.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>

namespace {

using rayverify::ray_sphere;
using rayverify::root_pair;

// A fixed, portable sequence of doubles in [-1, 1) (SplitMix64).
double next_unit(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1p-52 - 1.0;
}

// The header intersectors compiled here, inlined (flatten): were they called
// out of line, the linker would keep one copy of each template for the library
// and this file alike, and the comparison would compare a function with itself.
template <class T>
[[gnu::flatten]] root_pair<T> header_naive(const ray_sphere<T>& s) {
    return rayverify::intersectors::naive(s);
}
template <class T>
[[gnu::flatten]] root_pair<T> header_half_b(const ray_sphere<T>& s) {
    return rayverify::intersectors::half_b(s);
}

template <class T>
bool same(const root_pair<T>& a, const root_pair<T>& b) {
    return a.count == b.count && std::memcmp(&a.t0, &b.t0, sizeof(T)) == 0 && std::memcmp(&a.t1, &b.t1, sizeof(T)) == 0;
}

template <class T, class Header, class Library>
std::size_t differences(const char* name, Header header, const Library& library) {
    std::uint64_t state = 42;
    std::size_t differ = 0, cases = 0;
    for (int i = 0; i < 20000; ++i) {
        ray_sphere<double> g;
        g.origin = {4 * next_unit(state), 4 * next_unit(state), -10 + next_unit(state)};
        g.direction = {0.3 * next_unit(state), 0.3 * next_unit(state), 1};
        g.centre = {next_unit(state), next_unit(state), next_unit(state)};
        g.radius = 1.5 + next_unit(state);
        const ray_sphere<T> s = rayverify::rounded_to<T>(g);
        ++cases;
        if (!same(header(s), library(s))) ++differ;
    }
    std::printf("%s: %zu of %zu answers differ from the library's\n", name, differ, cases);
    return differ;
}

}  // namespace

int main(int argc, char** argv) {
    const bool unguarded = argc > 1 && std::string_view(argv[1]) == "--unguarded";
    std::size_t differ = 0;
    for (const char* name : {"naive", "half_b"}) {
        const rayverify::variant* v = rayverify::find_builtin_variant(name);
        if (v == nullptr) {
            std::printf("no built-in variant %s\n", name);
            return 2;
        }
        const bool naive = std::string_view(name) == "naive";
        differ += differences<double>(name, naive ? header_naive<double> : header_half_b<double>, v->run_double);
        differ += differences<float>(name, naive ? header_naive<float> : header_half_b<float>, v->run_float);
    }
    if (unguarded) return differ > 0 ? 0 : 1;
    return differ == 0 ? 0 : 1;
}
