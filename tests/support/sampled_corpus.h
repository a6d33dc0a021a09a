// A corpus for the sanitized suite. A test whose point is numeric agreement
// over a whole corpus directory (byte-identical reports, say) audits every
// case in the default suite; in the sanitized suite it audits one case line
// in `sanitized_stride` of every file (each file's comment lines kept, so
// every family and header is still read), which takes the same code paths
// past the sanitizers in a fraction of the time.
#pragma once

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "process.h"
#include "sanitized.h"

namespace rayverify::test_support {

class sampled_corpus {
public:
    explicit sampled_corpus(const std::filesystem::path& corpus) : dir_(corpus) {
        const bool sampling = sanitized_stride > 1;
        if (sampling) {
            scratch_.emplace("sampled_corpus");
            dir_ = scratch_->path() / corpus.filename();
            std::filesystem::create_directories(dir_);
        }
        for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
            if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
            std::ifstream in(entry.path());
            std::ofstream out;
            if (sampling) out.open(dir_ / entry.path().filename());
            std::size_t case_line = 0;
            for (std::string line; std::getline(in, line);) {
                const bool comment = line.empty() || line[0] == '#';
                const bool kept = comment || case_line++ % sanitized_stride == 0;
                if (kept && !comment) ++case_count_;
                if (kept && sampling) out << line << '\n';
            }
        }
    }
    // The directory to audit: the corpus itself, or its sample.
    const std::filesystem::path& path() const { return dir_; }
    // How many cases that directory's files hold (a report counts its lines by them).
    std::size_t case_count() const { return case_count_; }

private:
    std::filesystem::path dir_;
    std::size_t case_count_ = 0;
    std::optional<scratch_directory> scratch_;  // the sample's, in the sanitized build
};

}  // namespace rayverify::test_support
