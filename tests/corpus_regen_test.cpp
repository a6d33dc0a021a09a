// `rayverify corpus regen`: the shipped corpus is exactly what its manifest
// regenerates, and --check catches any change, naming file and line. Tampering
// happens in temporary copies (--corpus-dir), never in corpus/.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "corpus/manifest.h"
#include "core/input_error.h"
#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using namespace rayverify::test_support;


void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

class Regen : public testing::Test {
protected:
    scratch_directory scratch_{"rayverify_regen_test"};
    const fs::path dir_ = scratch_.path();
};

TEST_F(Regen, ShippedCorpusMatchesItsManifest) {
    const command_result r = run_cli(std::string("corpus regen --check --corpus-dir ") + RAYVERIFY_CORPUS_DIR);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("match"), std::string::npos) << r.output;
}

TEST_F(Regen, ShippedManifestListsEveryFamilyAndEveryCorpusFile) {
    const auto entries = rayverify::read_manifest(fs::path(RAYVERIFY_CORPUS_DIR) / "MANIFEST");
    std::set<std::string> families, files;
    std::size_t total = 0;
    for (const auto& e : entries) {
        families.insert(e.family);
        files.insert(e.file);
        total += e.count;
        EXPECT_GE(e.count, 300u) << e.file;
        EXPECT_LE(e.count, 1000u) << e.file;
    }
    for (const auto& f : rayverify::generator_families()) EXPECT_TRUE(families.count(std::string(f.name))) << f.name;
    for (const auto& entry : fs::recursive_directory_iterator(RAYVERIFY_CORPUS_DIR)) {
        if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
        const std::string relative = fs::relative(entry.path(), RAYVERIFY_CORPUS_DIR).generic_string();
        EXPECT_TRUE(files.count(relative)) << relative << " is shipped but not in the manifest";
    }
    std::uintmax_t bytes = 0;
    for (const auto& file : files) bytes += fs::file_size(fs::path(RAYVERIFY_CORPUS_DIR) / file);
    EXPECT_LT(bytes, 4u << 20) << "the shipped corpus must stay a few MB";
    EXPECT_GT(total, 9000u);
}

TEST_F(Regen, CheckFailsOnATamperedCopyNamingFileAndLine) {
    fs::copy(RAYVERIFY_CORPUS_DIR, dir_ / "corpus", fs::copy_options::recursive);
    const fs::path victim = dir_ / "corpus" / "edge" / "behind.txt";
    std::string text = read_text(victim);
    // Line 10: change the last hex digit of its radius.
    std::size_t start = 0;
    for (int line = 1; line < 10; ++line) start = text.find('\n', start) + 1;
    const std::size_t end = text.find('\n', start);
    char& digit = text[end - 4];
    digit = digit == '1' ? '2' : '1';
    write_text(victim, text);

    const command_result r = run_cli("corpus regen --check --corpus-dir " + (dir_ / "corpus").string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("edge/behind.txt:10:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 of "), std::string::npos) << r.output;

    // regen repairs it, and then the check passes.
    const command_result repaired = run_cli("corpus regen --corpus-dir " + (dir_ / "corpus").string());
    EXPECT_EQ(repaired.exit_code, 0) << repaired.output;
    EXPECT_EQ(read_text(victim), read_text(fs::path(RAYVERIFY_CORPUS_DIR) / "edge" / "behind.txt"));
    EXPECT_EQ(run_cli("corpus regen --check --corpus-dir " + (dir_ / "corpus").string()).exit_code, 0);
}

TEST_F(Regen, RegenIsByteIdenticalAcrossRunsAndEqualsGenerate) {
    write_text(dir_ / "MANIFEST", "# test\nsub/a.txt tiny_sphere 40 5 1\nb.txt near_tangent_hit_f32 30 2 1\n");
    ASSERT_EQ(run_cli("corpus regen --corpus-dir " + dir_.string()).exit_code, 0);
    const std::string a = read_text(dir_ / "sub" / "a.txt"), b = read_text(dir_ / "b.txt");
    ASSERT_EQ(run_cli("corpus regen --corpus-dir " + dir_.string()).exit_code, 0);
    EXPECT_EQ(read_text(dir_ / "sub" / "a.txt"), a);
    EXPECT_EQ(read_text(dir_ / "b.txt"), b);
    EXPECT_EQ(run_cli("corpus generate --family tiny_sphere --count 40 --seed 5").output, a);
    ASSERT_EQ(run_cli("corpus generate --family tiny_sphere --count 40 --seed 5 -o " + (dir_ / "c.txt").string()).exit_code,
              0);
    EXPECT_EQ(read_text(dir_ / "c.txt"), a);
    EXPECT_NE(a.find("--family tiny_sphere --count 40 --seed 5 (generator version 1)"), std::string::npos);

    fs::remove(dir_ / "b.txt");
    const command_result missing = run_cli("corpus regen --check --corpus-dir " + dir_.string());
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_NE(missing.output.find("b.txt: missing"), std::string::npos) << missing.output;
    write_text(dir_ / "b.txt", b.substr(0, b.size() - 1));  // no final newline
    EXPECT_EQ(run_cli("corpus regen --check --corpus-dir " + dir_.string()).exit_code, 1);
}

TEST_F(Regen, BadManifestIsAnInputErrorNamingLineAndField) {
    write_text(dir_ / "MANIFEST", "a.txt uniform 10 1 1\nb.txt nope 10 1 1\n");
    command_result r = run_cli("corpus regen --corpus-dir " + dir_.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("MANIFEST:2: field 'family'"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "a.txt")) << "nothing is written when the manifest is bad";

    write_text(dir_ / "MANIFEST", "a.txt uniform ten 1 1\n");
    r = run_cli("corpus regen --check --corpus-dir " + dir_.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("MANIFEST:1: field 'count'"), std::string::npos) << r.output;

    write_text(dir_ / "MANIFEST", "a.txt uniform 10 1 9\n");
    r = run_cli("corpus regen --corpus-dir " + dir_.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("field 'version'"), std::string::npos) << r.output;

    write_text(dir_ / "MANIFEST", "../a.txt uniform 10 1 1\n");
    EXPECT_EQ(run_cli("corpus regen --corpus-dir " + dir_.string()).exit_code, 2);
    write_text(dir_ / "MANIFEST", "a.txt uniform 10 1\n");
    r = run_cli("corpus regen --corpus-dir " + dir_.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("field 'version'"), std::string::npos) << r.output;
    EXPECT_EQ(run_cli("corpus regen --corpus-dir " + (dir_ / "nowhere").string()).exit_code, 2);

    // Lines as every text input is read (core/text_lines.h): CRLF ends read, a NUL byte refused.
    write_text(dir_ / "MANIFEST", "# CRLF\r\na.txt uniform 10 1 1\r\n");
    EXPECT_EQ(run_cli("corpus regen --corpus-dir " + dir_.string()).exit_code, 0);
    write_text(dir_ / "MANIFEST", std::string("a.txt uniform 10 1 1\nb.txt\0 uniform 10 1 1\n", 43));
    r = run_cli("corpus regen --corpus-dir " + dir_.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("MANIFEST:2: line contains a NUL byte"), std::string::npos) << r.output;
}

TEST(CompareLines, NamesTheFirstDifferingLine) {
    using rayverify::compare_lines;
    EXPECT_FALSE(compare_lines("a\nb\n", "a\nb\n"));
    const auto d = compare_lines("a\nb\nc\n", "a\nB\nc\n");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->line, 2u);
    EXPECT_EQ(d->expected, "b");
    EXPECT_EQ(d->actual, "B");
    const auto shorter = compare_lines("a\nb\n", "a\n");
    ASSERT_TRUE(shorter);
    EXPECT_EQ(shorter->line, 2u);
    EXPECT_EQ(shorter->actual, "");
    const auto newline = compare_lines("a\n", "a");
    ASSERT_TRUE(newline);
    EXPECT_EQ(newline->line, 1u);
}

TEST_F(Regen, HuntWritesPasteableCorpusLinesWithProvenance) {
    const fs::path out = dir_ / "hunt.txt";
    const command_result r = run_cli("hunt --variant naive --precision float --objective misclass --seconds 0 --evaluations 3000 "
                         "--finds 1 -o " + out.string());
    ASSERT_EQ(r.exit_code, 1) << r.output;
    const std::string text = read_text(out);
    EXPECT_NE(text.find("# rayverify hunt: naive/float, objective misclass"), std::string::npos) << text;
    EXPECT_NE(text.find("# find 1: "), std::string::npos) << text;
    // The finds audit as disagreements when read back.
    const command_result audit = run_cli("audit --corpus " + out.string() + " --variant naive --precision float");
    EXPECT_EQ(audit.exit_code, 1) << audit.output;
    // A pasted line reproduces it in explain.
    EXPECT_NE(r.output.find("hunt-naive-float-misclass-search-1-1 hunt_uniform "), std::string::npos) << r.output;

    const command_result ulp = run_cli("hunt --variant naive --precision double --seconds 0 --evaluations 2000 -o " +
                           (dir_ / "ulp.txt").string());
    EXPECT_EQ(ulp.exit_code, 0) << ulp.output;
    EXPECT_NE(read_text(dir_ / "ulp.txt").find("lower bound"), std::string::npos);

    const command_result bad = run_cli("hunt --variant naive --family nope -o " + (dir_ / "bad.txt").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.output.find("field '--family'"), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(dir_ / "bad.txt"));
}

}  // namespace
