// The shipped corpus, audited with every built-in variant: the findings that
// make each textbook formula's reputation must be there, and the good forms
// must stay good. These are floors and ceilings, not exact counts, so the
// corpus can grow without rewriting the test.
#include <gtest/gtest.h>

#include "compare/audit.h"
#include "corpus/corpus_io.h"

namespace rayverify {
namespace {

class ShippedCorpus : public testing::Test {
protected:
    static void SetUpTestSuite() {
        cases_ = new std::vector<corpus_case>(read_corpus({RAYVERIFY_CORPUS_DIR}));
        totals_ = new audit_totals(run_audit(*cases_, targets_for(builtin_variants())));
    }
    static void TearDownTestSuite() {
        delete totals_;
        delete cases_;
    }

    static const target_tally& tally(const std::string& label, const std::string& family = "") {
        for (std::size_t i = 0; i < totals_->targets.size(); ++i)
            if (totals_->targets[i].label() == label)
                return family.empty() ? totals_->overall[i] : totals_->by_family.at(family)[i];
        throw std::runtime_error("no target " + label);
    }
    static std::size_t count(const target_tally& t, verdict_kind k) { return t.verdicts[static_cast<int>(k)]; }

    static std::vector<corpus_case>* cases_;
    static audit_totals* totals_;
};
std::vector<corpus_case>* ShippedCorpus::cases_ = nullptr;
audit_totals* ShippedCorpus::totals_ = nullptr;

TEST_F(ShippedCorpus, EveryCaseIsValidAndEveryFamilyPresent) {
    EXPECT_EQ(totals_->invalid_cases[0], 0u);
    EXPECT_EQ(totals_->invalid_cases[1], 0u);
    for (const char* family : {"uniform", "tangent_exact", "near_tangent", "far_sphere", "on_surface", "inside"})
        EXPECT_GE(totals_->cases_by_family.count(family), 1u) << family;
}

TEST_F(ShippedCorpus, NaiveFloatLosesFarSpheresAndHearnBakerLosesFewer) {
    const auto& naive = tally("naive/float", "far_sphere");
    const auto& hearn_baker = tally("hearn_baker/float", "far_sphere");
    EXPECT_GT(count(naive, verdict_kind::false_miss), 0u);
    EXPECT_LT(count(hearn_baker, verdict_kind::false_miss) + count(hearn_baker, verdict_kind::false_hit),
              count(naive, verdict_kind::false_miss) + count(naive, verdict_kind::false_hit));
    // And it is far more accurate when both classify right (RTG ch.7).
    EXPECT_LT(hearn_baker.errors[rayverify::error_figure::near_root_ulp].median * 10, naive.errors[rayverify::error_figure::near_root_ulp].median);
}

TEST_F(ShippedCorpus, HearnBakerDoubleGetsEveryFarSphereRight) {
    EXPECT_EQ(tally("hearn_baker/double", "far_sphere").disagreements(), 0u);
    EXPECT_GT(tally("naive/double", "far_sphere").disagreements(), 0u);
}

TEST_F(ShippedCorpus, StableRootsGivesNaNAtTheTangentPoint) {
    // b = 0 and Δ = 0: q = 0 and C/q = 0/0.
    EXPECT_GT(count(tally("stable_roots/double", "tangent_exact"), verdict_kind::non_finite), 0u);
    EXPECT_EQ(count(tally("naive/double", "tangent_exact"), verdict_kind::non_finite), 0u);
}

TEST_F(ShippedCorpus, UnitDirectionVariantsRefuseNonUnitDirections) {
    for (const char* label : {"seed003_reduced/double", "seed004_early_out/float", "geometric/double"})
        EXPECT_GT(count(tally(label, "tangent_exact"), verdict_kind::contract_violation), 0u) << label;
    EXPECT_EQ(count(tally("naive/double"), verdict_kind::contract_violation), 0u);
}

TEST_F(ShippedCorpus, SeedVariantsShowTheirKnownFailures) {
    // seed003's absolute 1e-7 tangent margin merges real double hits.
    EXPECT_GT(count(tally("seed003_reduced/double"), verdict_kind::false_tangent), 0u);
    // geometric's |L|² − t_ca² cancels: roots land on the wrong side near the surface.
    EXPECT_GT(count(tally("geometric/double", "on_surface"), verdict_kind::wrong_side), 0u);
    // Exactly tangent lines split into two roots in float.
    EXPECT_GT(count(tally("naive/float", "tangent_exact"), verdict_kind::tangent_split), 0u);
}

}  // namespace
}  // namespace rayverify
