// The floating-point environment of a thread: flush-to-zero, denormals-are-
// zero, the rounding mode and which exceptions trap. rayverify's own
// arithmetic (the oracle, the judge, every measure) runs in the IEEE default
// (round to nearest, gradual underflow, every exception masked); a target
// runs in the environment it would run in where it is deployed: the one its
// library set when it was loaded (GCC's crtfastmath.o sets FTZ+DAZ for a
// library linked with -ffast-math), or one chosen with --fp-env.
//
// The state is the hardware's, per thread: on x86-64 MXCSR (FTZ bit 15, DAZ
// bit 6, rounding bits 13-14, exception masks bits 7-12; its status flags
// are not part of it) and the x87 control word (precision, rounding, masks);
// on aarch64 FPCR (FZ, RMode, the trap enables, AH); elsewhere the rounding
// mode and the trapped exceptions of <cfenv>. On x86-64 and aarch64 reading
// it costs a few instructions, inline here, so it can be checked around every
// call into foreign code and on every case the oracle solves.
#pragma once

#include <cfenv>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace rayverify {

// How the state is read: on x86-64 MXCSR and the x87 control word, on
// aarch64 FPCR (their bits, which fp_environment.cpp also writes and
// describes), elsewhere <cfenv>'s trapped exceptions where glibc tells them.
namespace fp_registers {
#if defined(__x86_64__)
// MXCSR's control bits (its low six bits are sticky status flags).
inline constexpr std::uint32_t mxcsr_controls = 0xFFC0;
inline constexpr std::uint32_t mxcsr_daz = 1u << 6, mxcsr_ftz = 1u << 15;
inline constexpr std::uint32_t mxcsr_rounding_shift = 13, mxcsr_rounding = 3u << mxcsr_rounding_shift;
inline constexpr std::uint32_t mxcsr_mask_shift = 7, mxcsr_masks = 0x3Fu << mxcsr_mask_shift;
// The x87 control word's defined bits: exception masks (0-5), precision (8-9), rounding (10-11).
inline constexpr std::uint16_t x87_defined = 0x0F3F;
inline constexpr std::uint16_t x87_default = 0x033F;  // every exception masked, extended precision, to nearest

inline std::uint16_t x87_control_word() {
    std::uint16_t word = 0;
    __asm__ __volatile__("fnstcw %0" : "=m"(word));
    return word;
}
#elif defined(__aarch64__)
inline constexpr std::uint64_t fpcr_fz = 1ull << 24, fpcr_ah = 1ull << 1;
inline constexpr unsigned fpcr_rmode_shift = 22;
inline constexpr std::uint64_t fpcr_rmode = 3ull << fpcr_rmode_shift;

inline std::uint64_t read_fpcr() {
    std::uint64_t value = 0;
    __asm__ __volatile__("mrs %0, fpcr" : "=r"(value));
    return value;
}
#else
inline int trapped_exceptions() {
#if defined(__GLIBC__)
    return fegetexcept();
#else
    return 0;
#endif
}
#endif
}  // namespace fp_registers

struct fp_state {
#if defined(__x86_64__)
    std::uint32_t mxcsr = 0;        // control bits only (status flags cleared)
    std::uint16_t x87_control = 0;  // the control word's defined bits
#elif defined(__aarch64__)
    std::uint64_t fpcr = 0;
#else
    int rounding = 0;  // fegetround()
    int traps = 0;     // trapped exceptions, where the platform can say
#endif
    bool operator==(const fp_state&) const = default;
};

// The calling thread's state, and setting it.
inline fp_state current_fp_state() {
    fp_state s;
#if defined(__x86_64__)
    s.mxcsr = _mm_getcsr() & fp_registers::mxcsr_controls;
    s.x87_control = static_cast<std::uint16_t>(fp_registers::x87_control_word() & fp_registers::x87_defined);
#elif defined(__aarch64__)
    s.fpcr = fp_registers::read_fpcr();
#else
    s.rounding = std::fegetround();
    s.traps = fp_registers::trapped_exceptions();
#endif
    return s;
}
void set_fp_state(const fp_state& state);

// Round to nearest, gradual underflow, every exception masked (x87: extended
// precision): what the C and C++ standards start a program in.
inline fp_state ieee_default_fp_state() {
    fp_state s;
#if defined(__x86_64__)
    s.mxcsr = fp_registers::mxcsr_masks;  // 0x1F80: masked, to nearest, no FTZ or DAZ
    s.x87_control = fp_registers::x87_default;
#elif defined(__aarch64__)
    s.fpcr = 0;
#else
    s.rounding = FE_TONEAREST;
    s.traps = 0;
#endif
    return s;
}
inline bool is_ieee_default(const fp_state& s) { return s == ieee_default_fp_state(); }

// Make the calling thread's environment the IEEE default if it is not; true
// when it had to (something left it changed).
inline bool restore_ieee_default() {
    if (is_ieee_default(current_fp_state())) [[likely]]
        return false;
    set_fp_state(ieee_default_fp_state());
    return true;
}

// "the IEEE default", or what differs from it, e.g. "FTZ+DAZ",
// "rounding upward", "FTZ+DAZ, FE_INVALID trapped", "x87 precision single".
std::string describe_fp_state(const fp_state& s);

// What `--fp-env` names: flush-to-zero, denormals-are-zero and a rounding
// mode, every exception masked. Names: ieee, ftz, daz, upward, downward,
// toward_zero, joined with '+' (ftz+daz, ftz+daz+upward).
struct fp_environment_spec {
    enum class rounding { nearest, upward, downward, toward_zero };
    bool ftz = false;
    bool daz = false;
    rounding round = rounding::nearest;
    bool operator==(const fp_environment_spec&) const = default;
};

// nullopt for a name that is none of the above (or names two roundings).
std::optional<fp_environment_spec> parse_fp_environment(std::string_view name);
// The canonical name: "ieee", "ftz+daz", "ftz+daz+upward", ...
std::string fp_environment_name(const fp_environment_spec& spec);
// The hardware state it stands for, on this platform; nullopt where the
// platform cannot set it (FTZ/DAZ beyond x86-64 and aarch64, DAZ on aarch64,
// where FZ flushes inputs and outputs together).
std::optional<fp_state> fp_state_for(const fp_environment_spec& spec);

// How a chosen environment reads in reports: "FTZ+DAZ (--fp-env ftz+daz)".
std::string chosen_fp_environment_text(const fp_environment_spec& spec);

// The names --fp-env takes, for help texts.
inline constexpr std::string_view fp_environment_names = "ieee, ftz, daz, ftz+daz, upward, downward, toward_zero";

// The environments chosen with --fp-env: one for every target, and one per
// target name (which wins). A target named by neither runs in its own: the
// IEEE default, or the one its library set when it was loaded.
struct fp_environment_choice {
    std::optional<fp_environment_spec> every;
    std::map<std::string, fp_environment_spec, std::less<>> by_target;
    std::optional<fp_environment_spec> for_target(std::string_view name) const {
        if (const auto it = by_target.find(name); it != by_target.end()) return it->second;
        return every;
    }
    bool empty() const { return !every && by_target.empty(); }
};

}  // namespace rayverify
