// What the results-reader fuzz target checks on one input, shared with
// tests/fuzz_regression_test.cpp (which replays every seed and saved finding).
// The input's first byte chooses the format: 'c' CSV, 'j' JSON lines, 'n' an
// npy whose companion comes first, up to the first NUL byte; an odd second
// byte reads with a scope of ids (the input's cases known first).
// Returns the violated invariant, or nullopt when all hold.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>

#include "core/input_error.h"
#include "corpus/exchange.h"
#include "refusal_check.h"

namespace rayverify::fuzz {

// A value of a float results file is a float (NaN and infinities included).
inline bool is_float_value(double x) { return std::isnan(x) || static_cast<double>(static_cast<float>(x)) == x; }

// The reader either throws an input_error naming the file it was given (or
// the npy's companion) and, for text, a line that exists, or returns answers
// whose counts are 0, 1 or 2, whose values in a float file are floats, and,
// with a scope, only for ids of the scope.
inline std::optional<std::string> check_results_reader_input(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return std::nullopt;
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const char kind = all[0];
    const bool scoped = (static_cast<unsigned char>(all[1]) & 1) != 0;
    std::string_view body = all.substr(2);
    results_scope scope;
    for (const char* id : {"a", "b", "c1", "q\"uote"}) scope.add(id);
    exchange_format format = exchange_format::csv;
    std::string file = "fuzz.csv";
    std::optional<std::string> companion;
    if (kind == 'j') {
        format = exchange_format::jsonl;
        file = "fuzz.jsonl";
    } else if (kind == 'n') {
        format = exchange_format::npy;
        file = "fuzz.npy";
        const std::size_t nul = body.find('\0');
        companion = std::string(body.substr(0, nul));
        body = nul == std::string_view::npos ? std::string_view{} : body.substr(nul + 1);
    } else if (kind != 'c') {
        return std::nullopt;
    }
    results_file r;
    try {
        r = parse_results(file, body, format, companion, scoped ? &scope : nullptr);
    } catch (const input_error& e) {
        if (format == exchange_format::npy) {
            if (e.file() != "fuzz.npy" && e.file() != "fuzz.json") return "error names file '" + e.file() + "': " + e.what();
            return std::nullopt;
        }
        return check_refusal(e, body, file);
    } catch (const std::exception& e) {
        return "threw something other than input_error: " + std::string(e.what());
    }
    const auto check = [&](const recorded_answer& a, const std::string& id) -> std::optional<std::string> {
        if (a.roots.count < 0 || a.roots.count > 2) return "count " + std::to_string(a.roots.count) + " accepted";
        if (r.prec == precision::binary32 && (!is_float_value(a.roots.t0) || !is_float_value(a.roots.t1)))
            return "a double accepted in a float file for '" + id + "'";
        if (scoped && !id.empty() && !scope.ids.count(id)) return "an answer to no case accepted: '" + id + "'";
        return std::nullopt;
    };
    for (const auto& [id, a] : r.book->by_id)
        if (auto broken = check(a, id)) return broken;
    for (const recorded_answer& a : r.rows)
        if (auto broken = check(a, "")) return broken;
    if (scoped && r.rows.size() > scope.cases) return "more npy rows than the scope's cases accepted";
    return std::nullopt;
}

}  // namespace rayverify::fuzz
