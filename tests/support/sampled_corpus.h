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
        if (sanitized_stride == 1) return;
        scratch_.emplace("sampled_corpus");
        dir_ = scratch_->path() / corpus.filename();
        std::filesystem::create_directories(dir_);
        for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
            if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
            std::ifstream in(entry.path());
            std::ofstream out(dir_ / entry.path().filename());
            std::size_t case_line = 0;
            for (std::string line; std::getline(in, line);)
                if (line.empty() || line[0] == '#' || case_line++ % sanitized_stride == 0) out << line << '\n';
        }
    }
    // The directory to audit: the corpus itself, or its sample.
    const std::filesystem::path& path() const { return dir_; }

private:
    std::filesystem::path dir_;
    std::optional<scratch_directory> scratch_;  // the sample's, in the sanitized build
};

}  // namespace rayverify::test_support
