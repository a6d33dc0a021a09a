// std::mt19937_64's exact sequence, with seeding paid for as drawn. The
// generators seed one engine per case (so that a case depends on its family,
// seed and index only) and draw a few dozen numbers from it; the standard
// engine first fills and twists all 312 words of its state. The first
// 312 − 156 outputs depend only on the initial words up to 156 beyond them:
// this engine computes those words as they are needed and twists each
// output's word alone, and hands over to a std::mt19937_64 (advanced to the
// same place) should a case ever draw more. tests/generators_test.cpp checks
// the outputs against std::mt19937_64's for many seeds, past the hand-over.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <span>

namespace rayverify {

class lazily_seeded_mt19937_64 {
public:
    using result_type = std::uint64_t;
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return ~result_type{0}; }

    explicit lazily_seeded_mt19937_64(result_type seed) : seed_(seed) { initial_[0] = seed; }

    result_type operator()() {
        if (drawn_ >= prefix) return draw_from_standard_engine();
        const std::size_t k = drawn_++;
        fill_initial_to(k + shift);
        // The twist of word k (n = 312, m = 156, r = 31), then the tempering.
        const result_type y = (initial_[k] & upper_mask) | (initial_[k + 1] & lower_mask);
        result_type z = initial_[k + shift] ^ (y >> 1) ^ ((y & 1) ? twist_matrix : 0);
        z ^= (z >> 29) & 0x5555555555555555ULL;
        z ^= (z << 17) & 0x71D67FFFEDA60000ULL;
        z ^= (z << 37) & 0xFFF7EEE000000000ULL;
        return z ^ (z >> 43);
    }

    // The initial words every first draw needs, computed for several engines
    // (none drawn from yet) in one loop: each engine's seeding recurrence is a
    // chain of dependent multiplications, and side by side the chains overlap.
    static void seed_together(std::span<lazily_seeded_mt19937_64* const> engines) {
        for (std::size_t i = 0; i < shift; ++i)
            for (lazily_seeded_mt19937_64* e : engines) e->initial_[i + 1] = next_initial(e->initial_[i], i + 1);
        for (lazily_seeded_mt19937_64* e : engines) e->filled_ = shift;
    }

private:
    static constexpr std::size_t words = 312, shift = 156, prefix = words - shift;

    static result_type next_initial(result_type previous, std::size_t i) {
        return 6364136223846793005ULL * (previous ^ (previous >> 62)) + i;
    }
    static constexpr result_type upper_mask = ~result_type{0} << 31, lower_mask = (result_type{1} << 31) - 1;
    static constexpr result_type twist_matrix = 0xB5026F5AA96619E9ULL;

    // The seeding recurrence x[i] = f·(x[i−1] ⊕ (x[i−1] ≫ 62)) + i, up to word `last`.
    void fill_initial_to(std::size_t last) {
        for (; filled_ < last; ++filled_) initial_[filled_ + 1] = next_initial(initial_[filled_], filled_ + 1);
    }

    result_type draw_from_standard_engine() {
        if (!standard_) {
            standard_ = std::make_unique<std::mt19937_64>(seed_);
            standard_->discard(prefix);
        }
        return (*standard_)();
    }

    result_type seed_;
    std::array<result_type, words> initial_;  // [0, filled_] computed
    std::size_t filled_ = 0;
    std::size_t drawn_ = 0;
    std::unique_ptr<std::mt19937_64> standard_;
};

}  // namespace rayverify
