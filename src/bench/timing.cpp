#include "bench/timing.h"

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>

#include "bench/collecting_reporter.h"
#include "bench/kernels.h"
#include "core/input_error.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify::bench {

bool target_met(double value, double limit, target_direction direction) {
    static const std::string forced = [] {
        const char* hook = std::getenv("RAYVERIFY_TEST_BENCH_TARGETS");
        return hook ? std::string(hook) : std::string();
    }();
    if (forced == "met") return true;
    if (forced == "missed") return false;
    return direction == target_direction::at_most ? value <= limit : value >= limit;
}
namespace {

// The family's cases valid at precision T, rounded to T.
template <class T>
std::vector<ray_sphere<T>> rounded_cases(const std::vector<corpus_case>& cases) {
    std::vector<ray_sphere<T>> out;
    using valid_in = std::conditional_t<std::is_same_v<T, float>, float, double>;
    for (const corpus_case& c : cases)
        if (validity<valid_in>(c.geometry) == invalid_reason::none) out.push_back(rounded_to<T>(c.geometry));
    return out;
}

// The timed loop: `kernel` is a concrete callable, and flatten makes GCC
// inline it (and the intersector) into the loop, as in a renderer's inner
// loop. Left to its heuristics GCC keeps the intersectors out of line, and
// returning root_pair<float> through registers then costs a store-forwarding
// stall that doubles the float time.
template <class T, class Kernel>
[[gnu::flatten]] void run_loop(benchmark::State& state, const std::vector<ray_sphere<T>>& cases, Kernel kernel) {
    for (auto _ : state) {
        for (const ray_sphere<T>& s : cases) {
            auto result = kernel(s);
            benchmark::DoNotOptimize(result);
        }
    }
}

template <class T, class Kernel>
double checksum_of(const std::vector<ray_sphere<T>>& cases, Kernel kernel) {
    double sum = 0;
    for (const ray_sphere<T>& s : cases) sum += kernel(s).count;
    return sum;
}

struct pending {
    timing_row row;
    std::function<void(benchmark::State&)> body;
};

timing_row measure(pending p, const timing_options& options) {
    collecting_reporter reporter;
    benchmark::RegisterBenchmark(p.row.label().c_str(), [&p](benchmark::State& state) { p.body(state); })
        ->Repetitions(options.repetitions)
        ->MinTime(options.min_time_s)
        ->MinWarmUpTime(options.warmup_s)
        ->ReportAggregatesOnly(false);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();
    timing_row row = std::move(p.row);
    const double per_pass = 1e9 / static_cast<double>(std::max<std::size_t>(row.cases, 1));
    for (const auto& run : reporter.repetitions) {
        const double iterations = static_cast<double>(run.iterations);
        row.ns_per_test.push_back(run.cpu_accumulated_time / iterations * per_pass);
        row.real_ns_per_test.push_back(run.real_accumulated_time / iterations * per_pass);
        row.tests.push_back(static_cast<std::uint64_t>(run.iterations) * row.cases);
    }
    if (!row.ns_per_test.empty()) {
        row.median = median_of(row.ns_per_test);
        row.real_median = median_of(row.real_ns_per_test);
        row.min = *std::min_element(row.ns_per_test.begin(), row.ns_per_test.end());
        row.max = *std::max_element(row.ns_per_test.begin(), row.ns_per_test.end());
    }
    return row;
}

}  // namespace

timing_row time_pass(timing_row row, const std::function<double()>& one_pass, const timing_options& options) {
    row.checksum = one_pass();
    return measure({std::move(row),
                    [&one_pass](benchmark::State& state) {
                        for (auto _ : state) {
                            double value = one_pass();
                            benchmark::DoNotOptimize(value);
                        }
                    }},
                   options);
}

double median_of(std::vector<double> values) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

namespace {

// The value of a /proc/cpuinfo line "key<blanks>: value" (empty when it has none).
std::string cpuinfo_value(const std::string& line) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) return {};
    const auto start = line.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? std::string() : line.substr(start);
}

}  // namespace

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) return cpuinfo_value(line);
    return "unknown";
}

machine_record read_machine_record() {
    machine_record m;
    m.cpu = cpu_model();
    m.hardware_threads = std::thread::hardware_concurrency();
    std::ifstream cpuinfo("/proc/cpuinfo");
    bool flags_read = false;
    for (std::string line; std::getline(cpuinfo, line);) {
        if (line.empty()) break;  // the first processor's block is enough
        if (line.rfind("cpu MHz", 0) == 0) {
            const std::string text = cpuinfo_value(line);
            char* end = nullptr;
            const double mhz = std::strtod(text.c_str(), &end);
            if (end != text.c_str() && mhz > 0) m.cpu_mhz = mhz;
        } else if (!flags_read && (line.rfind("flags", 0) == 0 || line.rfind("Features", 0) == 0)) {
            std::istringstream words(cpuinfo_value(line));
            for (std::string w; words >> w;) m.cpu_flags.push_back(w);
            flags_read = true;
        }
    }
    std::ifstream max_frequency("/sys/devices/system/cpu/cpu0/cpufreq/cpuinfo_max_freq");
    if (double khz = 0; max_frequency >> khz && khz > 0) m.cpu_max_mhz = khz / 1000;
    std::ifstream load("/proc/loadavg");
    if (std::array<double, 3> l{}; load >> l[0] >> l[1] >> l[2]) m.load_average = l;
    utsname name{};
    if (uname(&name) == 0) m.kernel = fmt::format("{} {} {}", name.sysname, name.release, name.machine);
    return m;
}

std::vector<timing_row> time_variants(const std::map<std::string, std::vector<corpus_case>>& cases_by_family,
                                      const timing_options& options,
                                      void (*on_progress)(std::size_t, std::size_t)) {
    for (const std::string& name : options.variants)
        if (!find_builtin_variant(name)) throw input_error("", 0, "--variant", fmt::format("unknown variant '{}'", name));
    // Timed through their functions: the plugins, and the engine ports (no inlined kernel).
    std::vector<variant> through_function = options.plugins;
    for (const variant& v : builtin_variants())
        if (!v.build.empty() && times_builtin(options, v.name)) through_function.push_back(v);

    // Inputs rounded once per family and precision; the bodies refer to them.
    struct family_inputs {
        std::vector<ray_sphere<float>> f;
        std::vector<ray_sphere<double>> d;
        std::vector<ray_sphere<long double>> ld;
    };
    std::map<std::string, family_inputs> inputs;
    for (const auto& [family, cases] : cases_by_family)
        inputs[family] = {rounded_cases<float>(cases), rounded_cases<double>(cases),
                          rounded_cases<long double>(cases)};

    std::vector<pending> work;
    for (const auto& [family, in] : inputs) {
        for_each_kernel([&, &in = in, &family = family](std::string_view name, auto kernel) {
            if (!times_builtin(options, name)) return;
            const auto add = [&](const char* prec, const auto& cases) {
                if (!times_precision(options, prec)) return;
                timing_row row;
                row.variant = name;
                row.precision = prec;
                row.family = family;
                row.cases = cases.size();
                row.checksum = checksum_of(cases, kernel);
                work.push_back({std::move(row), [&cases, kernel](benchmark::State& s) { run_loop(s, cases, kernel); }});
            };
            add("float", in.f);
            add("double", in.d);
            if constexpr (has_long_double<decltype(kernel)>) add("long double", in.ld);
        });
    }
    for (const variant& plugin : through_function) {
        for (const auto& [family, in] : inputs) {
            const auto add = [&, &family = family](const char* prec, const auto& cases) {
                using T = decltype(std::decay_t<decltype(cases)>::value_type::radius);
                if (!times_precision(options, prec)) return;
                timing_row row;
                row.variant = plugin.name;  // called through a function pointer (timing_json says so)
                row.precision = prec;
                row.family = family;
                row.cases = cases.size();
                const timed_pass_fn<T>& timed_pass = [&]() -> const timed_pass_fn<T>& {
                    if constexpr (std::is_same_v<T, float>)
                        return plugin.timed_pass_float;
                    else
                        return plugin.timed_pass_double;
                }();
                if (timed_pass) {
                    // Its own loop over the cases, the harness around the whole pass (registry.h).
                    std::function<long long()> pass = timed_pass(std::span<const ray_sphere<T>>(cases));
                    row.checksum = static_cast<double>(pass());
                    work.push_back({std::move(row), [pass = std::move(pass)](benchmark::State& s) {
                                        for (auto _ : s) {
                                            long long hits = pass();
                                            benchmark::DoNotOptimize(hits);
                                        }
                                    }});
                    return;
                }
                const auto through = [&plugin](const ray_sphere<T>& s) { return run_in(plugin, s, ray_interval<T>{}); };
                row.checksum = checksum_of(cases, through);
                work.push_back({std::move(row), [&cases, through](benchmark::State& s) { run_loop(s, cases, through); }});
            };
            if (plugin.runs_in(precision::binary32)) add("float", in.f);
            if (plugin.runs_in(precision::binary64)) add("double", in.d);
        }
    }
    if (options.include_oracle) {
        // The exact answers' own cost: the filtered oracle and the unfiltered
        // reference route, so the accuracy-vs-time plot spans the whole range.
        using solver = exact_solution (*)(const ray_sphere<double>&, precision, std::optional<double>,
                                          std::optional<double>);
        for (const auto& [name, solve] : {std::pair<const char*, solver>{"exact_oracle", &solve_exact},
                                          {"exact_reference", &solve_exact_reference}}) {
            for (const auto& [family, in] : inputs) {
                timing_row row;
                row.variant = name;
                row.precision = "exact";
                row.family = family;
                row.cases = in.d.size();
                const auto& cases = in.d;
                work.push_back({std::move(row), [&cases, solve = solve](benchmark::State& state) {
                                    for (auto _ : state)
                                        for (const ray_sphere<double>& s : cases) {
                                            exact_solution e = solve(s, precision::binary64, std::nullopt,
                                                                     std::nullopt);
                                            benchmark::DoNotOptimize(e);
                                        }
                                }});
            }
        }
    }

    std::vector<timing_row> rows;
    for (std::size_t i = 0; i < work.size(); ++i) {
        rows.push_back(measure(std::move(work[i]), options));
        if (on_progress) on_progress(i + 1, work.size());
    }
    return rows;
}

}  // namespace rayverify::bench
