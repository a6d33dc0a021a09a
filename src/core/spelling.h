// "Did you mean": the known name nearest a misspelt one, for the messages
// that refuse an unknown variant or family name.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rayverify {

// Levenshtein distance (insertions, deletions, substitutions).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// The one known name within a third of the word's length (at least 2) of
// edits, the nearest; nullopt when none is, or two are equally near.
inline std::optional<std::string> nearest_name(std::string_view word, const std::vector<std::string>& known) {
    const std::size_t most = std::max<std::size_t>(2, word.size() / 3);
    std::optional<std::string> best;
    std::size_t best_distance = most + 1;
    bool tie = false;
    for (const std::string& name : known) {
        const std::size_t d = edit_distance(word, name);
        if (d < best_distance) {
            best = name;
            best_distance = d;
            tie = false;
        } else if (d == best_distance) {
            tie = true;
        }
    }
    return tie ? std::nullopt : best;
}

// " (did you mean 'x'?)" or "".
inline std::string did_you_mean(std::string_view word, const std::vector<std::string>& known) {
    const std::optional<std::string> nearest = nearest_name(word, known);
    return nearest ? " (did you mean '" + *nearest + "'?)" : std::string();
}

}  // namespace rayverify
