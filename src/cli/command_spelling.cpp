// Shards of one run may be started from another working directory, through
// another path to the executable or to the input (a checkout here, an
// installed copy there, a job array's node-local copy): their recorded command
// lines are compared with those spellings set aside. What the paths named is
// checked apart: the build by its build record, the input by its fingerprint,
// plugins by the targets they describe.
#include <fmt/format.h>

#include <algorithm>

#include "cli/commands.h"

namespace rayverify::cli {

namespace {

// Options whose value is a path; its spelling is set aside (what the file
// holds is compared instead: the input's fingerprint, the digests of results
// files and plugins).
bool takes_path(const std::string& option) {
    static const char* const options[] = {"--corpus", "--plugin", "--scene", "--results"};
    return std::find(std::begin(options), std::end(options), option) != std::end(options);
}

// The words of a normalised command grouped as an option with its values (or
// a leading word, the subcommand, alone), e.g. "--variant naive".
std::vector<std::string> option_groups(const std::vector<std::string>& words) {
    std::vector<std::string> groups;
    for (const std::string& w : words) {
        if (groups.empty() || w.starts_with("-"))
            groups.push_back(w);
        else
            groups.back() += " " + w;
    }
    return groups;
}

std::string listed(const std::vector<std::string>& groups) {
    std::string out;
    for (const std::string& g : groups) out += fmt::format("{}'{}'", out.empty() ? "" : ", ", g);
    return out;
}

}  // namespace

std::vector<std::string> command_words(const std::string& command_line) {
    std::vector<std::string> words;
    for (std::size_t at = 0; at <= command_line.size();) {
        const std::size_t end = std::min(command_line.find(' ', at), command_line.size());
        words.push_back(command_line.substr(at, end - at));
        at = end + 1;
    }
    return words;
}

std::vector<std::string> normalised_command(const std::string& recorded) {
    std::vector<std::string> out;
    const std::vector<std::string> words = command_words(recorded);
    bool path_next = false;
    for (std::size_t i = 1; i < words.size(); ++i) {  // words[0]: the executable, however reached
        std::string word = words[i], value;
        if (const std::size_t equals = word.find('='); word.starts_with("--") && equals != std::string::npos) {
            value = word.substr(equals + 1);
            word.resize(equals);
        }
        const bool is_path = path_next;
        path_next = takes_path(word) && value.empty();
        out.push_back(is_path ? "PATH" : word);
        if (!value.empty()) out.push_back(takes_path(word) ? "PATH" : value);
    }
    return out;
}

std::optional<std::string> command_difference(const std::string& a, const std::string& b, const std::string& a_name,
                                              const std::string& b_name) {
    const std::vector<std::string> groups_a = option_groups(normalised_command(a));
    const std::vector<std::string> groups_b = option_groups(normalised_command(b));
    if (groups_a == groups_b) return std::nullopt;
    std::vector<std::string> sorted_a = groups_a, sorted_b = groups_b, only_a, only_b;
    std::sort(sorted_a.begin(), sorted_a.end());
    std::sort(sorted_b.begin(), sorted_b.end());
    std::set_difference(sorted_a.begin(), sorted_a.end(), sorted_b.begin(), sorted_b.end(), std::back_inserter(only_a));
    std::set_difference(sorted_b.begin(), sorted_b.end(), sorted_a.begin(), sorted_a.end(), std::back_inserter(only_b));
    std::string what;
    if (!only_a.empty()) what += fmt::format("{} has {}", a_name, listed(only_a));
    if (!only_b.empty()) what += fmt::format("{}{} has {}", what.empty() ? "" : "; ", b_name, listed(only_b));
    if (what.empty()) what = fmt::format("the same options in another order ({} vs {})", listed(groups_a),
                                         listed(groups_b));
    return what;
}

}  // namespace rayverify::cli
