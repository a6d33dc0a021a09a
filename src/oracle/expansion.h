// Floating-point expansions: an exact value held as an unevaluated sum of
// doubles (J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and
// Fast Robust Geometric Predicates", Discrete & Computational Geometry 18,
// 1997; the algorithms of predicates.c, written here from the paper). Sums of
// expansions and products with a double are exact; the oracle uses them to
// evaluate polynomials of the inputs exactly without big numbers, where
// double-words alone cannot reach the accuracy a figure needs.
//
// An expansion's components are strongly nonoverlapping and in order of
// increasing magnitude, with no zero component (0 is the empty expansion):
// Shewchuk's Theorems 13 and 19 keep that so for every result built from
// single doubles with the operations below, under round-to-nearest-even. The
// value's sign is then its largest component's.
//
// Range: exact only while no product underflows or overflows; the caller
// keeps its operands in a range where none does (the oracle's filter range).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/double_word.h"

namespace rayverify {

// Components c[0..n) hold the value; the rest of the array is never read,
// written or copied (the bound N of a product grows fast, and zeroing or
// copying all of it cost more than the arithmetic).
template <int N>
struct expansion {
    std::array<double, N> c;
    int n = 0;

    expansion() = default;
    expansion(const expansion& other) : n(other.n) { std::copy_n(other.c.begin(), n, c.begin()); }
    // The same value in a larger bound.
    template <int M>
        requires(M < N)
    explicit expansion(const expansion<M>& other) : n(other.n) {
        std::copy_n(other.c.begin(), n, c.begin());
    }
    expansion& operator=(const expansion& other) {
        n = other.n;
        std::copy_n(other.c.begin(), n, c.begin());
        return *this;
    }
};

inline expansion<1> expansion_of(double x) {
    expansion<1> e;
    if (x != 0) e.c[e.n++] = x;
    return e;
}

// h = e + f exactly, or e − f with `subtract` (Fast-Expansion-Sum with zero
// elimination: merge the components by magnitude, then one running
// two_sum); h, not e or f, holds at most R components, which the caller's
// bound on the sum keeps within.
template <bool subtract = false, int R, int M, int K>
void add_into(expansion<R>& h, const expansion<M>& e, const expansion<K>& f) {
    h.n = 0;
    if (e.n == 0 && f.n == 0) return;
    int i = 0, j = 0;
    // The next component by magnitude (ties: e's first).
    const auto take = [&]() {
        if (j >= f.n || (i < e.n && std::fabs(e.c[i]) <= std::fabs(f.c[j]))) return e.c[i++];
        return subtract ? -f.c[j++] : f.c[j++];
    };
    double q = take();
    while (i < e.n || j < f.n) {
        const dword s = two_sum(q, take());
        if (s.l != 0) h.c[h.n++] = s.l;
        q = s.h;
    }
    if (q != 0) h.c[h.n++] = q;
}

template <int M, int K>
expansion<M + K> operator+(const expansion<M>& e, const expansion<K>& f) {
    expansion<M + K> h;
    add_into(h, e, f);
    return h;
}

template <int M, int K>
expansion<M + K> operator-(const expansion<M>& e, const expansion<K>& f) {
    expansion<M + K> h;
    add_into<true>(h, e, f);
    return h;
}

// h = e × b exactly (Scale-Expansion with zero elimination); h holds at
// most 2·e.n components.
template <int R, int M>
void scale_into(expansion<R>& h, const expansion<M>& e, double b) {
    h.n = 0;
    if (e.n == 0 || b == 0) return;
    const dword first = two_prod(e.c[0], b);
    if (first.l != 0) h.c[h.n++] = first.l;
    double q = first.h;
    for (int i = 1; i < e.n; ++i) {
        const dword product = two_prod(e.c[i], b);
        const dword low = two_sum(q, product.l);
        if (low.l != 0) h.c[h.n++] = low.l;
        const dword high = fast_two_sum(product.h, low.h);
        if (high.l != 0) h.c[h.n++] = high.l;
        q = high.h;
    }
    if (q != 0) h.c[h.n++] = q;
}

template <int M>
expansion<2 * M> operator*(const expansion<M>& e, double b) {
    expansion<2 * M> h;
    scale_into(h, e, b);
    return h;
}

// e × f exactly: the sum of e scaled by each component of f, accumulated in
// two buffers in turn (the partial sums are never copied), the first chosen
// so that the last sum lands in the one returned.
template <int M, int K>
expansion<2 * M * K> operator*(const expansion<M>& e, const expansion<K>& f) {
    expansion<2 * M * K> h, other;
    if (f.n == 0) return h;
    // f.n − 1 sums follow the first scaling: an even number ends where it began.
    expansion<2 * M * K>* from = f.n % 2 == 1 ? &h : &other;
    expansion<2 * M * K>* to = from == &h ? &other : &h;
    scale_into(*from, e, f.c[0]);
    expansion<2 * M> term;
    for (int j = 1; j < f.n; ++j) {
        scale_into(term, e, f.c[j]);
        add_into(*to, *from, term);
        std::swap(from, to);
    }
    return h;
}

// sign of the exact value.
template <int N>
int sign_of(const expansion<N>& e) {
    if (e.n == 0) return 0;
    return e.c[e.n - 1] > 0 ? 1 : -1;
}

// The same value with nonadjacent components (Compress): each is then below
// the ulp of the one above it, so the largest few hold the value to a
// relative 2^−52 per component. (A sum or product leaves components that
// may be adjacent, the second largest as large as the largest's ulp and the
// third nearly as large as the second.)
// h holds e compressed, e's n components at most.
template <int R, int N>
void compress_into(expansion<R>& h, const expansion<N>& e) {
    h.n = 0;
    if (e.n == 0) return;
    std::array<double, N> g;
    int bottom = e.n - 1;
    double q = e.c[e.n - 1];
    for (int i = e.n - 2; i >= 0; --i) {
        const dword s = fast_two_sum(q, e.c[i]);
        if (s.l != 0) {
            g[bottom--] = s.h;
            q = s.l;
        } else {
            q = s.h;
        }
    }
    g[bottom] = q;
    for (int i = bottom + 1; i < e.n; ++i) {
        const dword s = fast_two_sum(g[i], q);
        q = s.h;
        if (s.l != 0) h.c[h.n++] = s.l;
    }
    h.c[h.n++] = q;
}

template <int N>
expansion<N> compressed(const expansion<N>& e) {
    expansion<N> h;
    compress_into(h, e);
    return h;
}

// The exact value of a compressed expansion (compressed, compress_into) as
// a double-word with a rigorous error bound: its two largest components
// (summed exactly) and, as the bound, the sum of the others' magnitudes.
template <int N>
bounded approximate_compressed(const expansion<N>& e) {
    if (e.n == 0) return exactly(0.0);
    const double high = e.c[e.n - 1], low = e.n >= 2 ? e.c[e.n - 2] : 0.0;
    double tail = 0;
    for (int k = 0; k + 2 < e.n; ++k) tail += std::fabs(e.c[k]);
    // At most N − 1 roundings in the sum, far inside the factor 1 + 2^−40.
    return {two_sum(high, low), tail * (1 + 0x1p-40) + 0x1p-600};
}

// Any expansion's exact value so approximated, compressed first.
template <int N>
bounded approximate(const expansion<N>& exact) {
    if (exact.n == 0) return exactly(0.0);
    return approximate_compressed(compressed(exact));
}

}  // namespace rayverify
