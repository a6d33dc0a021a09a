// `rayverify bench --benchmark-json FILE`: the timings in Google Benchmark's
// JSON format (context, then per benchmark one entry per repetition and the
// mean, median, stddev and cv aggregates), so that Google Benchmark's own
// tools (compare.py) and dashboards read them. Rendering only: the figures
// are the bench layer's timing rows.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/timing.h"

namespace rayverify {

struct benchmark_context {
    std::string command;     // as recorded in reports
    std::string cpu;         // CPU model
    unsigned cpus = 0;       // hardware threads
    std::string date;        // ISO 8601, local time with offset
    std::string host_name;
    std::vector<double> load_average;  // 1, 5 and 15 minutes
};

// What the machine says now (date, host, CPUs, load).
benchmark_context current_benchmark_context(const std::string& command);

// One benchmark per timing row, named variant/precision/family; times are
// per ray–sphere test in ns, "iterations" the tests timed.
nlohmann::ordered_json benchmark_json(const std::vector<bench::timing_row>& rows, const benchmark_context& context);

}  // namespace rayverify
