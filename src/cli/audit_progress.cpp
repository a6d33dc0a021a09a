// The audit's progress line: cases done out of the cases the input holds.
#include <fmt/format.h>

#include <fstream>

#include "cli/commands.h"
#include "corpus/corpus_io.h"

namespace rayverify::cli {
namespace {

// Case lines of the corpus files, counted as the reader counts them (blank
// and '#' lines skipped, a CSV file's header row); nullopt when a path cannot
// be read (the audit then reports that error itself).
std::optional<std::size_t> case_lines(const std::vector<std::filesystem::path>& paths) {
    std::size_t total = 0;
    try {
        for (const std::filesystem::path& path : paths)
            for (const std::filesystem::path& file : corpus_files(path)) {
                std::ifstream in(file, std::ios::binary);
                if (!in) return std::nullopt;
                bool header = file.extension() == ".csv";
                for (std::string line; std::getline(in, line);) {
                    const std::size_t first = line.find_first_not_of(" \t\r");
                    if (first == std::string::npos || line[first] == '#') continue;
                    if (header) {
                        header = false;
                        continue;
                    }
                    ++total;
                }
            }
    } catch (const std::exception&) {
        return std::nullopt;
    }
    return total;
}

}  // namespace

audit_progress::audit_progress(const std::vector<std::filesystem::path>& paths, const std::vector<generate_spec>& specs,
                               const shard_spec& shard)
    : line_("audit", "cases") {
    if (!line_.shown()) return;
    std::optional<std::size_t> total;
    if (!specs.empty()) {
        total = 0;
        for (const generate_spec& s : specs) *total += s.count;
    } else {
        total = case_lines(paths);
    }
    if (total) line_.set_total(static_cast<double>(shard.size_of(*total)));
}

std::function<void(std::size_t)> audit_progress::reporter() {
    if (!line_.shown()) return {};
    return [this](std::size_t done) { line_.update(static_cast<double>(done)); };
}

}  // namespace rayverify::cli
