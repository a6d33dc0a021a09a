// The layering of ARCHITECTURE.md, checked on the source tree: each layer
// includes only itself and the layers below it, and only the oracle's own
// files include CGAL, GMP or MPFR: its .cpp files and its private headers
// (src/oracle/internal/, which only the oracle's .cpp files include and
// which are not installed).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

namespace {

namespace fs = std::filesystem;

// The layer a source file belongs to: its folder, or for a layer's private
// headers (a folder `internal` inside it) the layer's folder.
std::string layer_of(const fs::path& file) {
    const fs::path folder = file.parent_path();
    return folder.filename() == "internal" ? folder.parent_path().filename().string() : folder.filename().string();
}

bool oracle_private_header(const fs::path& file) {
    return file.parent_path().filename() == "internal" && layer_of(file) == "oracle";
}

const std::map<std::string, int> layer_rank = {{"core", 0},   {"intersectors", 1}, {"oracle", 2}, {"compare", 3},
                                               {"plugin", 4}, {"corpus", 5},       {"scene", 6},  {"bench", 7},
                                               {"report", 8}, {"testing", 9},      {"cli", 10}};

TEST(Architecture, LayersIncludeOnlyThemselvesAndLayersBelow) {
    const std::regex project_include(R"re(^\s*#\s*include\s*"([a-z_]+)/)re");
    int files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(RAYVERIFY_SOURCE_DIR) / "src")) {
        if (!entry.is_regular_file()) continue;
        const std::string layer = layer_of(entry.path());
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
            const bool oracle_source = (entry.path().parent_path().filename() == "oracle" &&
                                        entry.path().extension() == ".cpp") ||
                                       oracle_private_header(entry.path());
            std::ifstream in(entry.path());
            for (std::string line; std::getline(in, line);) {
                if (std::regex_search(line, heavy)) {
                    EXPECT_TRUE(oracle_source) << entry.path() << " includes " << line;
                }
            }
        }
    }
}

TEST(Architecture, OraclePrivateHeadersAreIncludedOnlyByOracleSources) {
    const std::regex private_include(R"re(^\s*#\s*include\s*"oracle/internal/)re");
    int includes = 0;
    for (const char* tree : {"src", "tests", "fuzz", "examples"}) {
        for (const auto& entry : fs::recursive_directory_iterator(fs::path(RAYVERIFY_SOURCE_DIR) / tree)) {
            if (!entry.is_regular_file()) continue;
            const bool allowed = layer_of(entry.path()) == "oracle" &&
                                 (entry.path().extension() == ".cpp" || oracle_private_header(entry.path()));
            std::ifstream in(entry.path());
            for (std::string line; std::getline(in, line);) {
                if (!std::regex_search(line, private_include)) continue;
                ++includes;
                EXPECT_TRUE(allowed) << entry.path() << " includes " << line;
            }
        }
    }
    EXPECT_GT(includes, 0);
}

}  // namespace
