// The ideal side of a traced run (intersectors/traced.h): every value held
// in MPFR at exact_arithmetic::precision_bits = 16384 bits, round to
// nearest. Sums, differences, products and fused multiply-adds of the
// intersectors' few operations on float or double inputs fit in that many
// bits, so they are exact; a square root or a quotient is correctly rounded
// to 16384 bits (a relative error of 2^-16384, far below any step's).
// MPFR stays in ideal_arithmetic.cpp: this header names none of its types.
#pragma once

#include <memory>

#include "intersectors/traced.h"

namespace rayverify {

// What explain prints for one traced step.
struct step_figures {
    double exact = 0;           // the ideal value, rounded to nearest double
    double relative_error = 0;  // |computed − ideal| / |ideal|; 0 when both are 0, +inf when only the ideal is
    double bits_lost = 0;       // bits_lost(relative_error, digits)
};

class exact_arithmetic final : public ideal_arithmetic {
public:
    static constexpr long precision_bits = 16384;

    exact_arithmetic();
    ~exact_arithmetic() override;
    exact_arithmetic(const exact_arithmetic&) = delete;
    exact_arithmetic& operator=(const exact_arithmetic&) = delete;

    ideal_id exactly(double value) override;
    ideal_id add(ideal_id x, ideal_id y) override;
    ideal_id subtract(ideal_id x, ideal_id y) override;
    ideal_id multiply(ideal_id x, ideal_id y) override;
    ideal_id divide(ideal_id x, ideal_id y) override;
    ideal_id square_root(ideal_id x) override;
    ideal_id fused_multiply_add(ideal_id x, ideal_id y, ideal_id z) override;
    ideal_id negate(ideal_id x) override;
    ideal_id absolute(ideal_id x) override;
    ideal_id arc_tangent2(ideal_id y, ideal_id x) override;

    // The figures of a recorded step (its ideal handle from this arithmetic).
    step_figures measure(const traced_step& s);

private:
    struct values;
    std::unique_ptr<values> values_;
};

}  // namespace rayverify
