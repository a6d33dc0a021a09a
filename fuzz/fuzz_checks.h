// What the fuzz targets check on one input, shared with the regression test
// that replays every seed and every saved crash input (tests/fuzz_regression_test.cpp),
// so an input that once broke an invariant stays a test under g++ and the sanitizers.
// Each check returns the violated invariant, or nullopt when all hold.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "core/input_error.h"
#include "refusal_check.h"
#include "core/ray_sphere_case.h"
#include "corpus/corpus_io.h"
#include "oracle/mpfr_reference.h"
#include "oracle/oracle.h"

namespace rayverify::fuzz {

using violation = std::optional<std::string>;

inline bool same_bits(double a, double b) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) && std::signbit(a) == std::signbit(b);
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline std::vector<double> numbers_of(const corpus_case& c) {
    const auto& g = c.geometry;
    std::vector<double> v = {g.origin.x,    g.origin.y,    g.origin.z, g.direction.x, g.direction.y,
                             g.direction.z, g.centre.x,    g.centre.y, g.centre.z,    g.radius};
    for (const auto& bound : {c.tmin, c.tmax}) v.push_back(bound ? *bound : 0.0);
    return v;
}

// Corpus reader. Byte 0 picks the format (bit 0 set: CSV); the rest is the
// file's contents. The reader either throws an input_error naming this file
// and a line that exists, or returns cases with unique ids, each of which
// reads back bit for bit from its own text-corpus line.
inline violation check_corpus_reader_input(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return std::nullopt;
    const bool csv = (data[0] & 1) != 0;
    const std::string_view contents(reinterpret_cast<const char*>(data + 1), size - 1);
    const std::string file = csv ? "fuzz.csv" : "fuzz.txt";
    std::vector<corpus_case> cases;
    try {
        cases = parse_corpus(file, contents, csv);
    } catch (const input_error& e) {
        return check_refusal(e, contents, file);
    }
    std::unordered_set<std::string> ids;
    for (const corpus_case& c : cases) {
        if (!ids.insert(c.id).second) return "duplicate id accepted: " + c.id;
        if (!c.source.starts_with(file + ":")) return "source is not file:line: " + c.source;
        std::string line;
        try {
            line = format_case_line(c);
        } catch (const input_error& e) {
            return "a case read cannot be written: " + std::string(e.what());
        }
        std::vector<corpus_case> back;
        try {
            back = parse_corpus("again.txt", line + "\n", false);
        } catch (const input_error& e) {
            return "written line does not read back: " + line + ": " + e.what();
        }
        if (back.size() != 1 || back[0].id != c.id || back[0].family != c.family ||
            back[0].tmin.has_value() != c.tmin.has_value() || back[0].tmax.has_value() != c.tmax.has_value())
            return "written line reads back as another case: " + line;
        const auto x = numbers_of(c), y = numbers_of(back[0]);
        for (std::size_t i = 0; i < x.size(); ++i)
            if (!same_bits(x[i], y[i])) return "a number changed through the text format: " + line;
    }
    return std::nullopt;
}

// Bytes of an oracle input: ten little-endian doubles (o, d, c, r), then a
// byte whose bit 0 picks float. Shorter inputs are padded with zero bytes.
inline constexpr std::size_t oracle_input_bytes = 10 * sizeof(double) + 1;

inline std::string describe(const ray_sphere<double>& g, precision p) {
    std::string s = precision_name(p);
    for (double v : {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y, g.direction.z, g.centre.x,
                     g.centre.y, g.centre.z, g.radius})
        s += " " + hex_float(v);
    return s;
}

// The exact oracle on arbitrary doubles: agrees with the independent MPFR
// reference bit for bit, and its answer is self-consistent (roots ordered,
// a tangent's roots equal, the class matching the roots, correctly rounded
// roots, the front root matching the signs, negating d negating the roots).
inline violation check_oracle_input(const std::uint8_t* data, std::size_t size) {
    std::uint8_t bytes[oracle_input_bytes] = {};
    std::memcpy(bytes, data, std::min(size, oracle_input_bytes));
    double v[10];
    std::memcpy(v, bytes, sizeof v);
    const precision p = (bytes[80] & 1) ? precision::binary32 : precision::binary64;
    ray_sphere<double> g{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};

    // As in the audit, a case invalid at float never reaches the oracle at
    // float: validity<float> is checked first; only double invalidity is the
    // oracle's to report.
    const invalid_reason why = p == precision::binary32 ? validity<float>(g) : validity<double>(g);
    if (why != invalid_reason::none) {
        if (p == precision::binary64 && solve_exact(g, p).invalid != why)
            return std::string("invalid input not reported as ") + invalid_reason_name(why) + " for " + describe(g, p);
        return std::nullopt;
    }
    if (p == precision::binary32) g = rounded_to<double>(rounded_to<float>(g));  // what a float variant receives
    const std::string where = describe(g, p);
    const auto fail = [&](const std::string& what) -> violation { return what + " for " + where; };

    const exact_solution e = solve_exact(g, p);
    if (!e.valid()) return fail(std::string("valid input reported invalid: ") + invalid_reason_name(e.invalid));

    const reference_answer ref = solve_with_mpfr_reference(g, p);
    if (ref.cls != e.cls)
        return fail(std::string("class ") + line_class_name(e.cls) + ", MPFR reference says " +
                    line_class_name(ref.cls));
    if (e.cls == line_class::miss) {
        if (e.nearest_in_front) return fail("a miss with a root in front");
        return std::nullopt;
    }
    if (e.near_root.sign != ref.near_sign || e.far_root.sign != ref.far_sign) return fail("root signs differ from MPFR");
    if (!same_bits(e.near_root.rounded, ref.near_rounded) || !same_bits(e.far_root.rounded, ref.far_rounded))
        return fail("rounded roots differ from MPFR: " + hex_float(e.near_root.rounded) + " " +
                    hex_float(e.far_root.rounded) + " vs " + hex_float(ref.near_rounded) + " " +
                    hex_float(ref.far_rounded));

    // Invariants of the answer itself.
    if (e.cls == line_class::tangent && (!same_bits(e.near_root.rounded, e.far_root.rounded) ||
                                         e.near_root.sign != e.far_root.sign))
        return fail("tangent with two different roots");
    if (!(e.near_root.rounded <= e.far_root.rounded) || e.near_root.sign > e.far_root.sign)
        return fail("roots out of order");
    for (const root_index i : {root_index::near_root, root_index::far_root}) {
        const exact_root& r = e.root(i);
        if (p == precision::binary32 && static_cast<double>(static_cast<float>(r.rounded)) != r.rounded)
            return fail("a float root that is not a float");
        const bool side_ok = r.sign > 0 ? r.rounded >= 0 : r.sign < 0 ? r.rounded <= 0 : r.rounded == 0;
        if (!side_ok) return fail("rounded root on the other side of the origin than the exact root");
        if (!std::isfinite(r.rounded)) continue;  // the exact root lies beyond the precision's range
        const double error = e.root_ulp_error(i, r.rounded);
        if (!(error <= 0.5)) return fail("rounded root is " + std::to_string(error) + " ulp off");
        if ((error == 0) != (e.compare_to_root(r.rounded, i) == comparison::equal)) return fail("ulp error and comparison disagree");
    }
    const std::optional<root_index> front = e.near_root.sign > 0   ? std::optional(root_index::near_root)
                                            : e.far_root.sign > 0 ? std::optional(root_index::far_root)
                                                                  : std::nullopt;
    if (e.nearest_in_front != front) return fail("nearest root in front does not match the signs");

    // Metamorphic: negating d maps t to −t, so the roots swap and negate, exactly.
    ray_sphere<double> flipped = g;
    flipped.direction = {-g.direction.x, -g.direction.y, -g.direction.z};
    const exact_solution m = solve_exact(flipped, p);
    if (m.cls != e.cls || m.near_root.sign != -e.far_root.sign || m.far_root.sign != -e.near_root.sign)
        return fail("negating d changed the class or root signs");
    const auto negated_equal = [](double a, double b) { return a == -b || (a == 0 && b == 0); };
    if (!negated_equal(m.near_root.rounded, e.far_root.rounded) ||
        !negated_equal(m.far_root.rounded, e.near_root.rounded))
        return fail("negating d did not negate the roots");
    return std::nullopt;
}

}  // namespace rayverify::fuzz
