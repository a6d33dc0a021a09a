#include "report/benchmark_json.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <thread>
#include <tuple>

#include "report/audit_report.h"
#include "report/schema.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

struct moments {
    double mean = 0, median = 0, stddev = 0;
};

// Google Benchmark's aggregates: mean, median, sample standard deviation (n − 1; 0 for one repetition).
moments moments_of(const std::vector<double>& values) {
    moments m;
    if (values.empty()) return m;
    const double n = static_cast<double>(values.size());
    m.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
    m.median = bench::median_of(values);
    if (values.size() > 1) {
        double squares = 0;
        for (double v : values) squares += (v - m.mean) * (v - m.mean);
        m.stddev = std::sqrt(squares / (n - 1));
    }
    return m;
}

}  // namespace

benchmark_context current_benchmark_context(const std::string& command) {
    benchmark_context c;
    c.command = command;
    c.cpu = bench::cpu_model();
    c.cpus = std::thread::hardware_concurrency();
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%S%z", &local);
    c.date = date;
    if (c.date.size() > 5) c.date.insert(c.date.size() - 2, ":");  // +0000 → +00:00, as Google Benchmark writes it
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) == 0) c.host_name = host;
    double load[3] = {};
    if (getloadavg(load, 3) == 3) c.load_average = {load[0], load[1], load[2]};
    return c;
}

json benchmark_json(const std::vector<bench::timing_row>& rows, const benchmark_context& context) {
    json benchmarks = json::array();
    for (std::size_t index = 0; index < rows.size(); ++index) {
        const bench::timing_row& row = rows[index];
        const std::string name = fmt::format("{}/{}/{}", row.variant, row.precision, row.family);
        const std::size_t repetitions = row.ns_per_test.size();
        const json common = {{"family_index", index}, {"per_family_instance_index", 0}, {"run_name", name}};
        for (std::size_t k = 0; k < repetitions; ++k) {
            json run = {{"name", name}};
            run.update(common);
            run.update(json{{"run_type", "iteration"},
                            {"repetitions", repetitions},
                            {"repetition_index", k},
                            {"threads", 1},
                            {"iterations", k < row.tests.size() ? row.tests[k] : std::uint64_t{0}},
                            {"real_time", row.real_ns_per_test[k]},
                            {"cpu_time", row.ns_per_test[k]},
                            {"time_unit", "ns"}});
            benchmarks.push_back(run);
        }
        const moments cpu = moments_of(row.ns_per_test), real = moments_of(row.real_ns_per_test);
        const auto cv = [](const moments& m) { return m.mean > 0 ? m.stddev / m.mean : 0.0; };
        for (const auto& [aggregate, unit, real_value, cpu_value] :
             {std::tuple{"mean", "time", real.mean, cpu.mean}, std::tuple{"median", "time", real.median, cpu.median},
              std::tuple{"stddev", "time", real.stddev, cpu.stddev},
              std::tuple{"cv", "percentage", cv(real), cv(cpu)}}) {
            json entry = {{"name", fmt::format("{}_{}", name, aggregate)}};
            entry.update(common);
            entry.update(json{{"run_type", "aggregate"},
                              {"repetitions", repetitions},
                              {"threads", 1},
                              {"aggregate_name", aggregate},
                              {"aggregate_unit", unit},
                              {"iterations", repetitions},
                              {"real_time", real_value},
                              {"cpu_time", cpu_value},
                              {"time_unit", "ns"}});
            benchmarks.push_back(entry);
        }
    }
    json machine = {{"date", context.date},
                    {"host_name", context.host_name},
                    {"executable", "rayverify bench"},
                    {"num_cpus", context.cpus},
                    {"caches", json::array()},
                    {"load_avg", context.load_average},
                    {"cpu", context.cpu},
                    {"command", context.command},
                    {"rayverify", build_json()},
                    {"time_per", "one ray–sphere test (iterations: tests timed)"}};
    return {{"schema_version", schema_version::benchmark}, {"context", machine}, {"benchmarks", benchmarks}};
}

}  // namespace rayverify
