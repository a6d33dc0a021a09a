// What the baseline-reader fuzz target checks on one input, shared with
// tests/fuzz_regression_test.cpp (which replays every seed and saved finding).
// Returns the violated invariant, or nullopt when all hold.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>

#include "compare/gate.h"
#include "core/input_error.h"
#include "refusal_check.h"

namespace rayverify::fuzz {

// Bit-identical doubles (the figures are compared exactly: a value that moves
// through the text format would move the gate's limits).
inline bool same_value(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// Where two readings of one baseline differ, or nullopt.
inline std::optional<std::string> baseline_difference(const baseline& a, const baseline& b) {
    if (a.figures.size() != b.figures.size())
        return "figure count " + std::to_string(a.figures.size()) + " became " + std::to_string(b.figures.size());
    for (auto x = a.figures.begin(), y = b.figures.begin(); x != a.figures.end(); ++x, ++y) {
        if (!(x->first == y->first)) return "figure " + x->first.text() + " became " + y->first.text();
        if (!same_value(x->second, y->second)) return "the value of " + x->first.text() + " changed";
    }
    if (a.policies.size() != b.policies.size()) return "policy line count changed";
    for (std::size_t i = 0; i < a.policies.size(); ++i) {
        const policy_line &p = a.policies[i], &q = b.policies[i];
        if (p.scope != q.scope || p.key != q.key || !same_value(p.value, q.value))
            return "policy line " + std::to_string(i) + " changed: " + p.scope + " " + p.key;
        if (p.comments != q.comments) return "comments of policy line " + std::to_string(i) + " changed";
    }
    if (a.configurations != b.configurations) return "library lines or their comments changed";
    if (a.contracts != b.contracts) return "contract lines or their comments changed";
    if (a.allowed_missing != b.allowed_missing) return "allow-missing lines changed";
    if (a.format_comments != b.format_comments) return "comments above the format line changed";
    if (a.comments != b.comments) return "comments above the figures changed";
    if (a.trailing_comments != b.trailing_comments) return "trailing comments changed";
    return std::nullopt;
}

// The bytes are a baseline file. The reader either throws an input_error that
// names this file and a line that exists (and nothing else), or returns a
// baseline whose every figure is one of figure_names() for a target
// "variant/precision" with a value ≥ 0, whose ulp_slack policies are finite
// factors ≥ 1, and which the writer (`gate --update`) writes as text that
// reads back as the same baseline — figures bit for bit, policies and
// comments — and is written again byte for byte. --update with the
// baseline's own figures, set-ups and contracts changes nothing.
inline std::optional<std::string> check_baseline_reader_input(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const std::string file = "fuzz.baseline";
    baseline b;
    try {
        b = parse_baseline(file, text);
    } catch (const input_error& e) {
        return check_refusal(e, text, file);
    } catch (const std::exception& e) {
        return "threw something other than input_error: " + std::string(e.what());
    }

    const auto names = figure_names();
    for (const auto& [key, value] : b.figures) {
        if (std::find(names.begin(), names.end(), key.figure) == names.end())
            return "unknown figure accepted: " + key.text();
        if (key.target.find('/') == std::string::npos) return "target without a precision accepted: " + key.text();
        if (!(value >= 0)) return "negative or NaN value accepted for " + key.text();
    }
    for (const policy_line& p : b.policies) {
        if (p.key != "ulp_slack" && p.key != "count_slack") return "unknown policy key accepted: " + p.key;
        if (!(p.value >= 0)) return "negative or NaN policy accepted for " + p.scope;
        if (p.key == "ulp_slack" && !(p.value >= 1 && std::isfinite(p.value)))
            return "ulp_slack accepted below 1 or infinite for " + p.scope;
    }

    // What --update writes reads back as the same baseline.
    std::string written;
    baseline back;
    try {
        written = format_baseline(b);
        back = parse_baseline("again.baseline", written);
    } catch (const std::exception& e) {
        return "the written baseline does not read back: " + std::string(e.what()) + "\n" + written;
    }
    if (const auto changed = baseline_difference(b, back)) return "through the writer, " + *changed + "\n" + written;
    if (format_baseline(back) != written) return "writing the baseline read back gives other text\n" + written;
    // A run that gives the baseline's own figures, under its library set-ups and contracts.
    configuration_table setups, contracts;
    for (const auto& [variant, line] : b.configurations) setups[variant] = line.text;
    for (const auto& [variant, line] : b.contracts) contracts[variant] = line.text;
    if (const auto changed = baseline_difference(b, updated_baseline(b, b.figures, setups, contracts)))
        return "--update with the baseline's own figures: " + *changed;
    return std::nullopt;
}

}  // namespace rayverify::fuzz
