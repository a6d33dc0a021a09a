// A small table of values computed from doubles, for a caller that asks for
// the same doubles again soon (a per-case line prints the figures of targets
// that answer alike): a slot per hash of the double's bits (Fibonacci
// hashing), holding the last double that hashed to it and what was computed
// from it. The caller keeps the table, per thread.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace rayverify {

template <class Value, std::size_t slot_bits = 8>
class remembered_by_bits {
public:
    // compute(x) when x's slot holds another double, else what it gave for x.
    // NaN is never remembered (its slot's bits start as a NaN's, which no
    // lookup of a NaN is asked for: callers pass finite values).
    template <class Compute>
    const Value& of(double x, Compute&& compute) {
        const auto bits = std::bit_cast<std::uint64_t>(x);
        slot& s = slots_[(bits * 0x9E3779B97F4A7C15ull) >> (64 - slot_bits)];
        if (s.bits != bits) {
            s.value = compute(x);
            s.bits = bits;
        }
        return s.value;
    }

private:
    struct slot {
        std::uint64_t bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN());
        Value value{};
    };
    std::array<slot, std::size_t{1} << slot_bits> slots_{};
};

}  // namespace rayverify
