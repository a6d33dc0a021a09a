// A Google Benchmark reporter that keeps the per-repetition runs of the
// benchmarks registered at a time, so the bench layer computes its own
// medians and spreads. Internal to src/bench/ (Google Benchmark is PRIVATE).
#pragma once

#include <benchmark/benchmark.h>

#include <vector>

namespace rayverify::bench {

class collecting_reporter : public benchmark::BenchmarkReporter {
public:
    bool ReportContext(const Context&) override { return true; }
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs)
            if (run.run_type == Run::RT_Iteration && !run.error_occurred) repetitions.push_back(run);
    }
    std::vector<Run> repetitions;
};

}  // namespace rayverify::bench
