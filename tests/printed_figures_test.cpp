// Every error figure is printed correctly rounded to figure_significant_digits
// significant digits (compare/error_figures.h): printed_figure by hand, against
// glibc's printf on random doubles of every binade, and on what an audit of the
// shipped corpus writes (per-case lines and report.json), figure by figure,
// against the exact figures the judge measured.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "compare/audit.h"
#include "compare/error_figures.h"
#include "corpus/corpus_io.h"
#include "corpus/json_mapping.h"
#include "intersectors/registry.h"
#include "report/audit_report.h"
#include "report/json_line.h"

namespace rayverify {
namespace {

using json = nlohmann::ordered_json;

// The significant digits of a JSON number's spelling ("0.1235", "1.235e-07", "12340.0").
int significant_digits(std::string text) {
    if (const std::size_t e = text.find_first_of("eE"); e != std::string::npos) text.resize(e);
    std::string digits;
    for (char c : text)
        if (c >= '0' && c <= '9') digits += c;
    const std::size_t first = digits.find_first_not_of('0');
    if (first == std::string::npos) return 0;
    const std::size_t last = digits.find_last_not_of('0');
    return static_cast<int>(last - first + 1);
}

TEST(PrintedFigures, FourDigitsCorrectlyRoundedTiesToEven) {
    ASSERT_EQ(figure_significant_digits, 4);
    EXPECT_EQ(printed_figure(0.12345), 0.1235);   // the double lies above the decimal tie
    EXPECT_EQ(printed_figure(12345.0), 12340.0);  // an exact tie: to the even digit
    EXPECT_EQ(printed_figure(12355.0), 12360.0);
    EXPECT_EQ(printed_figure(99995.0), 100000.0);  // a tie carrying into the next decade (9999 is odd)
    EXPECT_EQ(printed_figure(99985.0), 99980.0);
    EXPECT_EQ(printed_figure(9.9995), 9.999);  // the double 9.99949999... lies below the tie
    EXPECT_EQ(printed_figure(0.5), 0.5);
    EXPECT_EQ(printed_figure(1.0 / 3.0), 0.3333);
    EXPECT_EQ(printed_figure(2.0 / 3.0), 0.6667);
    EXPECT_EQ(printed_figure(0x1p-60), 8.674e-19);
    EXPECT_EQ(printed_figure(3.0e300 + 1.0e297), 3.001e300);
    // The smallest subnormal prints as 4.941e-324, whose nearest double is itself.
    EXPECT_EQ(printed_figure(std::numeric_limits<double>::denorm_min()), std::numeric_limits<double>::denorm_min());
    EXPECT_EQ(printed_figure(0.0), 0.0);
    EXPECT_EQ(printed_figure(std::numeric_limits<double>::infinity()), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(std::isnan(printed_figure(std::numeric_limits<double>::quiet_NaN())));
    // 1.798e308 is beyond every double: the figure stays as it is.
    EXPECT_EQ(printed_figure(std::numeric_limits<double>::max()), std::numeric_limits<double>::max());
    EXPECT_EQ(printed_figure(std::optional<double>()), std::nullopt);
    EXPECT_EQ(printed_figure(std::optional<double>(0.12345)), std::optional<double>(0.1235));

    EXPECT_EQ(format_figure(0.12345), "0.1235");
    EXPECT_EQ(format_figure(12345.0), "1.234e+04");
    EXPECT_EQ(format_figure(0.5), "0.5");
    EXPECT_EQ(format_figure(0.0), "0");
    EXPECT_EQ(format_figure(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(format_figure(std::numeric_limits<double>::quiet_NaN()), "nan");
    EXPECT_NE(figure_printing_rule().find("4 significant digits"), std::string::npos);
}

// Against glibc's printf (exact decimal conversion, ties to even in the
// default rounding mode), on doubles of random bits: the same decimal; the
// figure's JSON spelling has at most four digits; printing is monotonic and
// printing a printed figure changes nothing.
TEST(PrintedFigures, AgreeWithPrintfOnRandomDoublesOfEveryBinade) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    std::mt19937_64 random(seed);
    double previous_x = 0, previous_printed = 0;
    for (int i = 0; i < 200000; ++i) {
        double x = std::bit_cast<double>(random() >> 1);  // every positive binade, subnormals included
        if (!std::isfinite(x) || x > 1.79e308) continue;
        if (i % 4 == 0) x = std::nextafter(printed_figure(x), 0.0);  // next to a printed decimal
        char text[64];
        std::snprintf(text, sizeof text, "%.3e", x);
        const double expected = std::strtod(text, nullptr);
        const double printed = printed_figure(x);
        ASSERT_EQ(printed, expected) << text << " from " << std::hexfloat << x;
        ASSERT_EQ(printed_figure(printed), printed) << text;
        ASSERT_LE(significant_digits(json_text(json(printed))), 4) << json_text(json(printed));
        if (x < previous_x) {
            ASSERT_LE(printed, previous_printed);
        } else {
            ASSERT_GE(printed, previous_printed);
        }
        previous_x = x;
        previous_printed = printed;
    }
}

// The four-digit scaling estimates a figure's decimal exponent from its
// binary one and puts the estimate right: every binade's first and last
// double, and the doubles next to each power of ten the fast range reaches
// (where the estimate is likeliest to be off), against printf; each with
// its neighbour above through printed_alike.
TEST(PrintedFigures, AgreeWithPrintfAtEveryBinadeEdgeAndPowerOfTen) {
    std::vector<double> values;
    for (int e = -1074; e <= 1023; ++e) {
        const double first = std::ldexp(1.0, e);
        values.push_back(first);
        if (e < 1023) values.push_back(std::nextafter(std::ldexp(1.0, e + 1), 0.0));
    }
    for (int k = -24; k <= 26; ++k) {
        const double power = std::pow(10.0, k);
        for (double x : {std::nextafter(power, 0.0), power, std::nextafter(power, INFINITY)}) values.push_back(x);
    }
    for (const double x : values) {
        char text[64];
        std::snprintf(text, sizeof text, "%.3e", x);
        ASSERT_EQ(printed_figure(x), std::strtod(text, nullptr)) << text << " from " << std::hexfloat << x;
        const double above = std::nextafter(x, INFINITY);
        if (std::isfinite(above)) {
            ASSERT_EQ(printed_alike(x, above), printed_figure(x) == printed_figure(above)) << std::hexfloat << x;
        }
    }
}

// Where arithmetic finds a figure's decimal, it is the one glibc's printf
// rounds the double to at four significant digits ("%.3e", ties to even),
// and the double nearest it is printed_figure's, bit for bit; on random
// doubles of every binade. It is found for nearly every figure an audit
// prints (a ULP or bits figure within 10^±18 of 1).
TEST(PrintedFigures, AFiguresDecimalIsThePrintedFigures) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    std::size_t found = 0, ordinary = 0, ordinary_found = 0;
    for (int i = 0; i < 400000; ++i) {
        const double x = std::bit_cast<double>(rng());
        printed_decimal d;
        const bool in_ordinary_range = std::isfinite(x) && std::fabs(x) >= 1e-18 && std::fabs(x) <= 1e18;
        ordinary += in_ordinary_range;
        if (!printed_figure_decimal(x, d)) continue;
        ++found;
        ordinary_found += in_ordinary_range;
        ASSERT_LE(d.digits, 10000u) << std::hexfloat << x;
        ASSERT_EQ(d.negative, std::signbit(x));
        // printf's four digits, "d.ddde±XX", as an integer and an exponent,
        // against the decimal's with trailing zeros dropped from both.
        char by_printf[40];
        std::snprintf(by_printf, sizeof by_printf, "%.3e", std::fabs(x));
        const std::string printf_text(by_printf);
        std::uint64_t printf_digits = std::stoull(printf_text.substr(0, 1) + printf_text.substr(2, 3));
        int printf_exponent = std::stoi(printf_text.substr(6)) - 3;
        std::uint64_t digits = d.digits;
        int exponent = d.exponent;
        for (; printf_digits % 10 == 0; printf_digits /= 10) ++printf_exponent;
        for (; digits % 10 == 0; digits /= 10) ++exponent;
        ASSERT_EQ(digits, printf_digits) << std::hexfloat << x << ": printf " << printf_text;
        ASSERT_EQ(exponent, printf_exponent) << std::hexfloat << x << ": printf " << printf_text;
        char text[48];
        char* end = std::to_chars(text, text + sizeof text, d.digits).ptr;
        *end++ = 'e';
        end = std::to_chars(end, text + sizeof text, d.exponent).ptr;
        double nearest = 0;
        std::from_chars(text, end, nearest);
        if (d.negative) nearest = -nearest;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(nearest), std::bit_cast<std::uint64_t>(printed_figure(x)))
            << std::hexfloat << x << ": " << std::string_view(text, end);
    }
    for (const double x : {0.0, -0.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
        printed_decimal none;
        EXPECT_FALSE(printed_figure_decimal(x, none)) << x;
    }
    std::printf("decimals found for %zu of 400000 random doubles, %zu of the %zu within 10^±18\n", found,
                ordinary_found, ordinary);
    EXPECT_GE(ordinary_found, ordinary * 99 / 100);
}

// printed_alike(a, b), which the audit asks of a figure's bounds, says
// whether the two print alike: against printed_figure on pairs a few ulps
// apart, pairs straddling a printed decimal's tie, and pairs far apart.
TEST(PrintedFigures, PrintedAlikeIsPrintedFigureEquality) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    std::mt19937_64 random(seed);
    int apart = 0;
    for (int i = 0; i < 200000; ++i) {
        const double a = std::bit_cast<double>(random() >> 1);
        if (!std::isfinite(a) || a > 1e300) continue;
        double b = a;
        switch (i % 4) {
            case 0: b = std::nextafter(a, INFINITY); break;
            case 1: {  // a figure's bounds: about 2^-47 apart
                b = a * (1 + 0x1p-47);
                break;
            }
            case 2: {  // either side of a tie of the fourth digit
                const double printed = printed_figure(a);
                const double ulp4 = std::fabs(printed_figure(std::nextafter(printed, INFINITY) * (1 + 1e-3)) - printed);
                const double tie = printed + ulp4 / 2;
                b = std::nextafter(tie, INFINITY);
                break;
            }
            default: b = a * 3; break;
        }
        if (!std::isfinite(b) || b < a) continue;
        const bool expected = printed_figure(a) == printed_figure(b);
        apart += !expected;
        ASSERT_EQ(printed_alike(a, b), expected) << std::hexfloat << a << " " << b;
    }
    EXPECT_GT(apart, 1000);  // the pairs that print apart are exercised too
    EXPECT_TRUE(printed_alike(0, 0));
    EXPECT_FALSE(printed_alike(0, 0x1p-900));
}

// Where printed_figure rounds without a decimal conversion (figures from
// about 1e-19 to 1e25): decimal ties and their neighbours a few ulps away,
// and doubles spread over the range, against printf.
TEST(PrintedFigures, AgreeWithPrintfAtDecimalTiesAcrossTheFastRange) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    std::mt19937_64 random(seed);
    std::vector<double> values;
    for (int i = 0; i < 50000; ++i) {
        // (n + 0.5)·10^e, n of four digits: the tie between n and n + 1 at that scale.
        const long n = 1000 + static_cast<long>(random() % 9000);
        const int e = static_cast<int>(random() % 48) - 24;
        char tie[40];
        std::snprintf(tie, sizeof tie, "%ld5e%d", n, e - 1);
        double x = std::strtod(tie, nullptr);
        for (int step = 0; step < 3; ++step) x = std::nextafter(x, 0.0);
        for (int step = 0; step < 7; ++step, x = std::nextafter(x, HUGE_VAL)) values.push_back(x);
        values.push_back(std::exp(std::uniform_real_distribution<double>(-46, 60)(random)));
    }
    for (const double x : values) {
        char text[64];
        std::snprintf(text, sizeof text, "%.3e", x);
        ASSERT_EQ(printed_figure(x), std::strtod(text, nullptr)) << text << " from " << std::hexfloat << x;
        ASSERT_EQ(printed_figure(-x), -std::strtod(text, nullptr)) << text;
    }
}

// The figures of one audited case, with the names per-case lines give them,
// from the judge's exact scores.
void expect_line_figures_printed(const audited_case& audited, const std::vector<audit_target>& targets,
                                 const json& line, std::size_t& figures) {
    for (std::size_t t = 0; t < targets.size(); ++t) {
        // The audit may hold an agreeing answer's figures as bounds
        // (case_score::figure_upper_bounds): the exact ones are judged again.
        const case_score& held = audited.outcomes[t].score;
        const case_score s = held.figure_upper_bounds ? exact_figures(targets[t], *audited.source, audited.outcomes[t],
                                                                      audited.exact_for(targets[t].prec))
                                                      : held;
        const json& result = line["results"][targets[t].label()];
        for (const error_figure_definition& f : error_figures) {
            const std::string name(f.case_name);
            if (f.figure == error_figure::hit_point_ulp) {
                if (!s.hit_point_ulp) continue;
                for (int axis = 0; axis < 3; ++axis) {
                    // A non-finite figure is written "inf" (json_number's spelling).
                    const std::optional<std::optional<double>> written = number_from_json(result[name][axis]);
                    ASSERT_TRUE(written && *written) << json_text(result[name]);
                    const double want = printed_figure((*s.hit_point_ulp)[axis]);
                    ASSERT_TRUE(**written == want || (std::isnan(**written) && std::isnan(want)));
                    ++figures;
                }
                continue;
            }
            const std::optional<double> exact = f.of_case(s);
            if (!exact || !std::isfinite(*exact)) continue;
            ASSERT_TRUE(result.contains(name)) << name;
            ASSERT_EQ(result[name].get<double>(), printed_figure(*exact)) << name << " of " << audited.source->id;
            ASSERT_LE(significant_digits(json_text(result[name])), 4) << json_text(result[name]);
            ++figures;
        }
    }
}

// Every figure of every per-case line of the shipped corpus, with every
// built-in variant, is the judge's exact figure rounded to four digits; every
// maximum, p99 and median of report.json is the audit's, rounded alike, and
// names the case that attains the exact maximum.
TEST(PrintedFigures, PerCaseLinesAndReportOfTheShippedCorpusPrintTheExactFiguresRounded) {
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    std::size_t figures = 0;
    const audit_totals totals = run_audit(cases, targets, [&](const audited_case& audited) {
        const json line = json::parse(per_case_line(audited, targets));
        expect_line_figures_printed(audited, targets, line, figures);
    });
    EXPECT_GT(figures, 50000u);

    const json report = audit_report_json(totals, run_context{});
    ASSERT_EQ(report["results"].size(), targets.size());
    std::size_t statistics = 0;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const json& entry = report["results"][t];
        for (const error_figure_definition& f : error_figures) {
            const error_statistics& s = totals.overall[t].errors[f.figure];
            if (s.count == 0 || !std::isfinite(s.max)) continue;
            const json& written = entry[std::string(f.name)];
            EXPECT_EQ(written["max"].get<double>(), printed_figure(s.max)) << f.name;
            EXPECT_EQ(written["p99"].get<double>(), printed_figure(s.p99)) << f.name;
            EXPECT_EQ(written["median"].get<double>(), printed_figure(s.median)) << f.name;
            EXPECT_EQ(written["max_case"].get<std::string>(), s.max_case) << f.name;
            for (const char* key : {"max", "p99", "median"}) EXPECT_LE(significant_digits(json_text(written[key])), 4);
            ++statistics;
        }
    }
    EXPECT_GT(statistics, 100u);
}

}  // namespace
}  // namespace rayverify
