#include "core/fp_environment.h"

#include <cfenv>
#include <utility>
#include <vector>

namespace rayverify {

using namespace fp_registers;  // the registers' bits (core/fp_environment.h)

namespace {

#if defined(__x86_64__)
void set_x87_control_word(std::uint16_t word) {
    // Only the defined bits change; the rest keep what the CPU has.
    std::uint16_t full = x87_control_word();
    full = static_cast<std::uint16_t>((full & ~x87_defined) | (word & x87_defined));
    __asm__ __volatile__("fldcw %0" : : "m"(full));
}

// The exceptions as MXCSR's masks (bits 7-12) and the x87 word's (bits 0-5) order them.
constexpr const char* exception_names[] = {"FE_INVALID", "denormal-operand", "FE_DIVBYZERO",
                                           "FE_OVERFLOW", "FE_UNDERFLOW", "FE_INEXACT"};
const char* rounding_name(unsigned mode) {  // x86's encoding: 0 nearest, 1 down, 2 up, 3 toward zero
    constexpr const char* names[] = {"to nearest", "downward", "upward", "toward zero"};
    return names[mode & 3];
}
#elif defined(__aarch64__)
// Trap enables: IOE 8, DZE 9, OFE 10, UFE 11, IXE 12, IDE 15.
constexpr std::pair<unsigned, const char*> fpcr_traps[] = {{8, "FE_INVALID"},    {9, "FE_DIVBYZERO"},
                                                           {10, "FE_OVERFLOW"},  {11, "FE_UNDERFLOW"},
                                                           {12, "FE_INEXACT"},   {15, "denormal-input"}};
void write_fpcr(std::uint64_t value) { __asm__ __volatile__("msr fpcr, %0" : : "r"(value)); }
const char* rounding_name(unsigned mode) {  // RMode: 0 nearest, 1 +inf, 2 -inf, 3 zero
    constexpr const char* names[] = {"to nearest", "upward", "downward", "toward zero"};
    return names[mode & 3];
}
#endif

std::string joined(const std::vector<std::string>& parts) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
    return out;
}

}  // namespace

void set_fp_state(const fp_state& s) {
#if defined(__x86_64__)
    // Keep the status flags as they are: only the controls change.
    _mm_setcsr((_mm_getcsr() & ~mxcsr_controls) | (s.mxcsr & mxcsr_controls));
    set_x87_control_word(s.x87_control);
#elif defined(__aarch64__)
    write_fpcr(s.fpcr);
#else
    std::fesetround(s.rounding);
#if defined(__GLIBC__)
    fedisableexcept(FE_ALL_EXCEPT);
    if (s.traps) feenableexcept(s.traps);
#endif
#endif
}

std::string describe_fp_state(const fp_state& s) {
    if (is_ieee_default(s)) return "the IEEE default";
    std::vector<std::string> parts;
#if defined(__x86_64__)
    const bool ftz = (s.mxcsr & mxcsr_ftz) != 0, daz = (s.mxcsr & mxcsr_daz) != 0;
    if (ftz || daz) parts.emplace_back(ftz && daz ? "FTZ+DAZ" : ftz ? "FTZ" : "DAZ");
    if (const unsigned mode = (s.mxcsr & mxcsr_rounding) >> mxcsr_rounding_shift)
        parts.push_back(std::string("rounding ") + rounding_name(mode));
    for (unsigned bit = 0; bit < 6; ++bit)
        if ((s.mxcsr & (1u << (mxcsr_mask_shift + bit))) == 0) parts.push_back(std::string(exception_names[bit]) + " trapped");
    // The x87 unit: its precision, and whatever of its rounding and traps
    // differs from the SSE unit's (fesetround and feenableexcept set both).
    std::vector<std::string> x87;
    const unsigned precision = (s.x87_control >> 8) & 3;
    if (precision != 3)
        x87.push_back(precision == 0 ? "precision single" : precision == 2 ? "precision double" : "precision reserved");
    const unsigned x87_mode = (s.x87_control >> 10) & 3, sse_mode = (s.mxcsr & mxcsr_rounding) >> mxcsr_rounding_shift;
    if (x87_mode != sse_mode) x87.push_back(std::string("rounding ") + rounding_name(x87_mode));
    for (unsigned bit = 0; bit < 6; ++bit) {
        const bool x87_trapped = (s.x87_control & (1u << bit)) == 0;
        const bool sse_trapped = (s.mxcsr & (1u << (mxcsr_mask_shift + bit))) == 0;
        if (x87_trapped != sse_trapped)
            x87.push_back(std::string(exception_names[bit]) + (x87_trapped ? " trapped" : " masked"));
    }
    if (!x87.empty()) parts.push_back("x87 " + joined(x87));
#elif defined(__aarch64__)
    if (s.fpcr & fpcr_fz) parts.emplace_back("FZ (flush to zero)");
    if (s.fpcr & fpcr_ah) parts.emplace_back("AH (alternate handling)");
    if (const unsigned mode = static_cast<unsigned>((s.fpcr & fpcr_rmode) >> fpcr_rmode_shift))
        parts.push_back(std::string("rounding ") + rounding_name(mode));
    for (const auto& [bit, name] : fpcr_traps)
        if (s.fpcr & (1ull << bit)) parts.push_back(std::string(name) + " trapped");
    if (parts.empty()) parts.emplace_back("FPCR other bits set");
#else
    switch (s.rounding) {
        case FE_UPWARD: parts.emplace_back("rounding upward"); break;
        case FE_DOWNWARD: parts.emplace_back("rounding downward"); break;
        case FE_TOWARDZERO: parts.emplace_back("rounding toward zero"); break;
        default: break;
    }
    if (s.traps) parts.emplace_back("exceptions trapped");
#endif
    return joined(parts);
}

std::optional<fp_environment_spec> parse_fp_environment(std::string_view name) {
    fp_environment_spec spec;
    bool rounding_named = false;
    if (name == "ieee") return spec;
    while (true) {
        const std::size_t plus = name.find('+');
        const std::string_view word = name.substr(0, plus);
        if (word == "ftz")
            spec.ftz = true;
        else if (word == "daz")
            spec.daz = true;
        else if (word == "upward" || word == "downward" || word == "toward_zero") {
            if (rounding_named) return std::nullopt;
            rounding_named = true;
            spec.round = word == "upward"     ? fp_environment_spec::rounding::upward
                         : word == "downward" ? fp_environment_spec::rounding::downward
                                              : fp_environment_spec::rounding::toward_zero;
        } else {
            return std::nullopt;
        }
        if (plus == std::string_view::npos) return spec;
        name.remove_prefix(plus + 1);
    }
}

std::string fp_environment_name(const fp_environment_spec& spec) {
    std::string out;
    const auto add = [&](const char* word) { out += (out.empty() ? "" : "+") + std::string(word); };
    if (spec.ftz) add("ftz");
    if (spec.daz) add("daz");
    switch (spec.round) {
        case fp_environment_spec::rounding::upward: add("upward"); break;
        case fp_environment_spec::rounding::downward: add("downward"); break;
        case fp_environment_spec::rounding::toward_zero: add("toward_zero"); break;
        case fp_environment_spec::rounding::nearest: break;
    }
    return out.empty() ? "ieee" : out;
}

std::string chosen_fp_environment_text(const fp_environment_spec& spec) {
    const std::optional<fp_state> state = fp_state_for(spec);
    return (state ? describe_fp_state(*state) : fp_environment_name(spec)) + " (--fp-env " + fp_environment_name(spec) + ")";
}

std::optional<fp_state> fp_state_for(const fp_environment_spec& spec) {
    fp_state s = ieee_default_fp_state();
#if defined(__x86_64__)
    if (spec.ftz) s.mxcsr |= mxcsr_ftz;
    if (spec.daz) s.mxcsr |= mxcsr_daz;
    // x86's encoding: 1 downward, 2 upward, 3 toward zero; the x87 unit rounds the same way.
    unsigned mode = 0;
    switch (spec.round) {
        case fp_environment_spec::rounding::downward: mode = 1; break;
        case fp_environment_spec::rounding::upward: mode = 2; break;
        case fp_environment_spec::rounding::toward_zero: mode = 3; break;
        case fp_environment_spec::rounding::nearest: break;
    }
    s.mxcsr |= mode << mxcsr_rounding_shift;
    s.x87_control = static_cast<std::uint16_t>(s.x87_control | (mode << 10));
#elif defined(__aarch64__)
    if (spec.ftz != spec.daz) return std::nullopt;  // FZ flushes inputs and outputs together
    if (spec.ftz) s.fpcr |= fpcr_fz;
    std::uint64_t mode = 0;  // RMode: 1 upward, 2 downward, 3 toward zero
    switch (spec.round) {
        case fp_environment_spec::rounding::upward: mode = 1; break;
        case fp_environment_spec::rounding::downward: mode = 2; break;
        case fp_environment_spec::rounding::toward_zero: mode = 3; break;
        case fp_environment_spec::rounding::nearest: break;
    }
    s.fpcr |= mode << fpcr_rmode_shift;
#else
    if (spec.ftz || spec.daz) return std::nullopt;
    switch (spec.round) {
        case fp_environment_spec::rounding::upward: s.rounding = FE_UPWARD; break;
        case fp_environment_spec::rounding::downward: s.rounding = FE_DOWNWARD; break;
        case fp_environment_spec::rounding::toward_zero: s.rounding = FE_TOWARDZERO; break;
        case fp_environment_spec::rounding::nearest: break;
    }
#endif
    return s;
}

}  // namespace rayverify
