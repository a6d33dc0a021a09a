// A positive length or error as m·2^e (m a double, e an int): the judge's
// scale figures (compare/judge.cpp) multiply and divide values from 2^−1074
// to 2^1024 whose products leave the double range although the figure itself
// does not. Scaling by powers of two is exact, so where nothing under- or
// overflows the figure is the same double as the plain formula's.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/float_bits.h"

namespace rayverify {

struct scaled {
    double m = 0;  // 0 only for an exact zero
    int e = 0;

    static scaled of(double x) {
        scaled s;
        s.m = split(std::fabs(x), s.e);
        return s;
    }
    friend scaled operator*(scaled a, scaled b) { return {a.m * b.m, a.e + b.e}; }
    friend scaled operator/(scaled a, scaled b) { return {a.m / b.m, a.e - b.e}; }
    // RN to double of m·2^e (one rounding, in ldexp), except that a nonzero
    // value below the smallest subnormal is that subnormal, never 0; above
    // the largest double, +inf.
    double value() const {
        if (m == 0) return 0;
        int k = 0;
        const double mantissa = split(m, k);
        const long exponent = static_cast<long>(e) + k;
        // A normal result: the product with 2^exponent is exact, as ldexp's.
        if (exponent >= -1021 && exponent <= 1023) return mantissa * exact_power_of_two(static_cast<int>(exponent));
        if (exponent > 1100) return std::numeric_limits<double>::infinity();
        if (exponent < -1100) return std::numeric_limits<double>::denorm_min();
        const double x = std::ldexp(mantissa, static_cast<int>(exponent));
        return x == 0 ? std::numeric_limits<double>::denorm_min() : x;
    }

private:
    // std::frexp: x = significand·2^e with 0.5 ≤ |significand| < 1. A normal
    // x from its bits (the judge splits several values for every agreeing
    // answer, and the libm calls were a few percent of an audit); the rest
    // (0, subnormals, non-finite) by std::frexp.
    static double split(double x, int& e) {
        const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
        const int biased = static_cast<int>((bits >> 52) & 0x7FF);
        if (biased == 0 || biased == 0x7FF) return std::frexp(x, &e);
        e = biased - 1022;
        return std::bit_cast<double>((bits & 0x800FFFFFFFFFFFFFull) | (std::uint64_t{1022} << 52));
    }
};

}  // namespace rayverify
