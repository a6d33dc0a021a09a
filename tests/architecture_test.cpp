// The layering of ARCHITECTURE.md, checked on the source tree: each layer
// includes only itself and the layers below it, and only the oracle's own
// .cpp files include CGAL, GMP or MPFR.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

namespace {

namespace fs = std::filesystem;

const std::map<std::string, int> layer_rank = {{"core", 0},   {"intersectors", 1}, {"oracle", 2}, {"compare", 3},
                                               {"plugin", 4}, {"corpus", 5},       {"scene", 6},  {"bench", 7},
                                               {"report", 8}, {"testing", 9},      {"cli", 10}};

TEST(Architecture, LayersIncludeOnlyThemselvesAndLayersBelow) {
    const std::regex project_include(R"re(^\s*#\s*include\s*"([a-z_]+)/)re");
    int files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(RAYVERIFY_SOURCE_DIR) / "src")) {
        if (!entry.is_regular_file()) continue;
        const std::string layer = entry.path().parent_path().filename().string();
        ASSERT_TRUE(layer_rank.count(layer)) << "file outside the known layers: " << entry.path();
        ++files;
        std::ifstream in(entry.path());
        std::size_t line_number = 0;
        for (std::string line; std::getline(in, line);) {
            ++line_number;
            std::smatch m;
            if (!std::regex_search(line, m, project_include)) continue;
            ASSERT_TRUE(layer_rank.count(m[1])) << entry.path() << ":" << line_number << " includes unknown " << m[1];
            EXPECT_LE(layer_rank.at(m[1]), layer_rank.at(layer))
                << entry.path() << ":" << line_number << ": layer " << layer << " may not include " << m[1];
        }
    }
    EXPECT_GT(files, 20);
}

TEST(Architecture, OnlyOracleSourcesIncludeCgalGmpMpfr) {
    const std::regex heavy(R"re(^\s*#\s*include\s*<(CGAL/|gmp|mpfr))re");
    for (const char* tree : {"src", "tests"}) {
        for (const auto& entry : fs::recursive_directory_iterator(fs::path(RAYVERIFY_SOURCE_DIR) / tree)) {
            if (!entry.is_regular_file()) continue;
            const bool oracle_source = entry.path().parent_path().filename() == "oracle" &&
                                       entry.path().extension() == ".cpp";
            std::ifstream in(entry.path());
            for (std::string line; std::getline(in, line);) {
                if (std::regex_search(line, heavy)) {
                    EXPECT_TRUE(oracle_source) << entry.path() << " includes " << line;
                }
            }
        }
    }
}

}  // namespace
