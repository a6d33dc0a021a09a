// Replays every fuzz seed and every saved fuzz finding through the checks
// the libFuzzer targets run (fuzz/*_checks.h), so that each input that
// once broke an invariant stays a test here, under g++ and the sanitizers.
// A crash input from tools/fuzz.sh goes to fuzz/regressions/<target>/.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../fuzz/baseline_fuzz_checks.h"
#include "../fuzz/fuzz_checks.h"
#include "../fuzz/results_fuzz_checks.h"
#include "../fuzz/scene_fuzz_checks.h"

namespace {

namespace fs = std::filesystem;

// Every file under fuzz/seeds/<target>/ and fuzz/regressions/<target>/.
std::vector<fs::path> inputs_of(const std::string& target) {
    std::vector<fs::path> files;
    for (const char* kind : {"seeds", "regressions"}) {
        const fs::path dir = fs::path(RAYVERIFY_SOURCE_DIR) / "fuzz" / kind / target;
        if (!fs::is_directory(dir)) continue;
        for (const auto& entry : fs::directory_iterator(dir))
            if (entry.is_regular_file()) files.push_back(entry.path());
    }
    return files;
}

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <class Check>
void replay(const std::string& target, Check check) {
    const auto files = inputs_of(target);
    EXPECT_GT(files.size(), 3u) << "seed corpus of " << target << " missing";
    for (const fs::path& file : files) {
        const std::string data = bytes_of(file);
        const auto broken = check(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
        EXPECT_FALSE(broken.has_value()) << file << ": " << broken.value_or("");
    }
}

TEST(FuzzRegression, CorpusReaderSeedsAndFindings) {
    replay("corpus_reader", rayverify::fuzz::check_corpus_reader_input);
}

TEST(FuzzRegression, OracleSeedsAndFindings) { replay("oracle", rayverify::fuzz::check_oracle_input); }

TEST(FuzzRegression, SceneReaderSeedsAndFindings) {
    replay("scene_reader", rayverify::fuzz::check_scene_reader_input);
}

TEST(FuzzRegression, ResultsReaderSeedsAndFindings) {
    replay("results_reader", rayverify::fuzz::check_results_reader_input);
}

TEST(FuzzRegression, BaselineReaderSeedsAndFindings) {
    replay("baseline_reader", rayverify::fuzz::check_baseline_reader_input);
}

}  // namespace
