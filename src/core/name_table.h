// The one way an enum gets its names: a table of (value, name) pairs, in enum
// order, and what reads it. Spec strings, options, their IsMember checks and
// shell completion all take the names from the enum's table.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rayverify {

template <class E, std::size_t N>
using name_table = std::array<std::pair<E, std::string_view>, N>;

// The name of value; "?" for a value the table lacks (unreachable for a valid enum value).
template <class E, std::size_t N>
constexpr std::string_view name_in(const name_table<E, N>& table, E value) {
    for (const auto& [v, name] : table)
        if (v == value) return name;
    return "?";
}

// The value named name; nullopt for an unknown name.
template <class E, std::size_t N>
constexpr std::optional<E> value_in(const name_table<E, N>& table, std::string_view name) {
    for (const auto& [v, n] : table)
        if (n == name) return v;
    return std::nullopt;
}

// Every name, in table order (an option's choices, its completion).
template <class E, std::size_t N>
std::vector<std::string> names_in(const name_table<E, N>& table) {
    std::vector<std::string> names;
    for (const auto& [v, name] : table) names.emplace_back(name);
    return names;
}

// The names joined with ", ", for a message that lists what is allowed.
template <class E, std::size_t N>
std::string allowed_names(const name_table<E, N>& table) {
    std::string out;
    for (const auto& [v, name] : table) out += (out.empty() ? "" : ", ") + std::string(name);
    return out;
}

}  // namespace rayverify
