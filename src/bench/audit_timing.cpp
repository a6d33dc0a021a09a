#include "bench/audit_timing.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <ctime>
#include <map>
#include <stdexcept>
#include <streambuf>

#include <fmt/format.h>

#include "bench/oracle_timing.h"
#include "bench/timing.h"
#include "compare/audit.h"
#include "corpus/case_stream.h"
#include "corpus/manifest.h"
#include "intersectors/registry.h"

namespace rayverify::bench {
namespace {

// An output stream that takes every character and keeps none: the per-case
// lines are rendered and written as the audit writes them, to no file.
class discarding_buffer : public std::streambuf {
public:
    std::uint64_t bytes = 0;  // taken so far

protected:
    int_type overflow(int_type c) override {
        ++bytes;
        return traits_type::not_eof(c);
    }
    std::streamsize xsputn(const char*, std::streamsize n) override {
        bytes += static_cast<std::uint64_t>(n);
        return n;
    }
};

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// Every target's own answer on every case it runs on, as audit_case asks for it.
class target_answers {
public:
    target_answers(const std::vector<corpus_case>& cases, const std::vector<audit_target>& targets)
        : cases_(cases), targets_(targets) {
        for (std::size_t t = 0; t < targets.size(); ++t)
            for (std::size_t i = 0; i < cases.size(); ++i) {
                if (targets[t].prec == precision::binary32) {
                    if (auto in = run_input<float>(targets[t], cases[i])) float_runs_.push_back({t, i, *in});
                } else if (auto in = run_input<double>(targets[t], cases[i])) {
                    double_runs_.push_back({t, i, *in});
                }
            }
    }
    // The number of roots answered: depends on every answer.
    double run() const { return run_all(float_runs_) + run_all(double_runs_); }

private:
    template <class T>
    struct run_of {
        std::size_t target, at;
        batch_case<T> input;
    };
    template <class T>
    double run_all(const std::vector<run_of<T>>& runs) const {
        double roots = 0;
        for (const run_of<T>& r : runs)
            roots += answer_of(targets_[r.target], cases_[r.at], r.input.input, r.input.interval).roots.count;
        return roots;
    }
    const std::vector<corpus_case>& cases_;
    const std::vector<audit_target>& targets_;
    std::vector<run_of<float>> float_runs_;
    std::vector<run_of<double>> double_runs_;
};

// `cases` in chunks as the audit reads a corpus, each case's index its place.
case_source chunks_of(const std::vector<corpus_case>& cases) {
    return [&cases, at = std::size_t{0}](std::vector<corpus_case>& chunk, std::vector<std::size_t>& indices) mutable {
        chunk.clear();
        indices.clear();
        for (; at < cases.size() && chunk.size() < case_stream::default_chunk; ++at) {
            chunk.push_back(cases[at]);
            indices.push_back(at);
        }
        return !chunk.empty();
    };
}

audit_timing_row time_family(const std::string& family, const std::vector<corpus_case>& cases,
                             const std::vector<audit_target>& targets, int repetitions, double min_time_s,
                             const whole_audit_pass& whole_pass) {
    audit_timing_row row;
    row.family = family;
    row.cases = cases.size();
    std::vector<ray_sphere<double>> inputs;
    for (const corpus_case& c : cases)
        if (validity<double>(c.geometry) == invalid_reason::none) inputs.push_back(c.geometry);

    const auto pass = [&](std::ostream* per_case) { return whole_pass(chunks_of(cases), targets, per_case); };
    // CPU ns per case-target of as many runs of `body` (over every case) as
    // fill min_time_s. A body returns a figure that depends on every result
    // it computed, summed into the row's checksum (so nothing is optimised away).
    const double case_targets = static_cast<double>(cases.size() * targets.size());
    const auto ns_per_case_target = [&](const auto& body) {
        const double start = cpu_seconds();
        int passes = 0;
        do {
            row.checksum += body();
            ++passes;
        } while (cpu_seconds() - start < min_time_s);
        return (cpu_seconds() - start) * 1e9 / (passes * case_targets);
    };
    const auto audit_ns = [&](std::ostream* per_case) {
        return ns_per_case_target([&] { return static_cast<double>(pass(per_case)); });
    };

    // The parts, each a larger piece of the pass than the one before.
    const target_answers answers(cases, targets);
    const auto oracle_only = [&] {
        double classes = 0;
        for (const corpus_case& c : cases)
            classes += static_cast<double>(solve_case(c, precision::binary64).cls) +
                       static_cast<double>(solve_case(c, precision::binary32).cls);
        return classes;
    };
    const auto judged_with = [&](const figure_request& wanted) {
        return [&cases, &targets, wanted] {
            double agreed = 0;
            audited_case judged;
            for (const corpus_case& c : cases) {
                audit_case_into(judged, c, targets, {}, wanted);
                for (const target_outcome& o : judged.outcomes) agreed += o.score.verdict == verdict_kind::agree;
            }
            return agreed;
        };
    };
    // As the audit timed asks (no per-case lines: no disagreement's sentence).
    figure_request every_figure = figure_request::audit(), verdicts_alone = figure_request::verdict_only();
    every_figure.details = verdicts_alone.details = false;
    const auto cases_judged = judged_with(every_figure);
    const auto verdicts_judged = judged_with(verdicts_alone);
    audit_hooks no_hooks;
    no_hooks.details = false;
    const auto stream_only = [&] {
        return static_cast<double>(audit_stream(chunks_of(cases), targets, 1, no_hooks).cases);
    };
    // Each repetition times naive, the audit and the audit with per-case
    // lines back to back, and the figures are medians of each repetition's
    // ratios: on a shared machine whose speed drifts, a ratio of neighbours
    // holds where a ratio of medians taken minutes apart does not.
    discarding_buffer discarded;
    std::ostream discard(&discarded);
    std::vector<double> naive, audit, ratio, per_case_ratio;
    std::array<std::vector<double>, 6> parts;  // as audit_parts::named orders them
    for (int r = 0; r < repetitions; ++r) {
        naive.push_back(time_naive(inputs, {1, std::max(min_time_s, 0.05)}, family));
        audit.push_back(audit_ns(nullptr));
        ratio.push_back(audit.back() / naive.back());
        per_case_ratio.push_back(audit_ns(&discard) / audit.back());
        const double answered = ns_per_case_target([&] { return answers.run(); });
        const double solved = ns_per_case_target(oracle_only);
        const double verdicts = ns_per_case_target(verdicts_judged);
        const double judged = ns_per_case_target(cases_judged);
        const double streamed = ns_per_case_target(stream_only);
        const double whole = audit_ns(nullptr);
        const double in_naive[] = {answered, solved, verdicts - answered - solved, judged - verdicts,
                                   streamed - judged, whole - streamed};
        for (std::size_t k = 0; k < parts.size(); ++k) parts[k].push_back(in_naive[k] / naive.back());
    }
    row.naive_ns = median_of(naive);
    row.audit_ns = median_of(audit);
    row.audit_ratio = median_of(ratio);
    row.per_case_ratio = median_of(per_case_ratio);
    discarded.bytes = 0;
    pass(&discard);
    row.per_case_bytes = static_cast<double>(discarded.bytes) / case_targets;
    double* const fields[] = {&row.parts.targets,  &row.parts.oracle,     &row.parts.verdicts,
                              &row.parts.figures,  &row.parts.accumulate, &row.parts.stability};
    for (std::size_t k = 0; k < parts.size(); ++k) *fields[k] = median_of(parts[k]);

    // How the oracle settled the figures: one more pass, counted.
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    counts = {};
    pass(nullptr);
    row.counts = counts;
    return row;
}

// Median of `repetitions` runs of generating `count` uniform cases.
generation_timing time_uniform_generation(int repetitions, std::size_t count) {
    std::vector<double> us;
    std::size_t bytes = 0;
    for (int r = 0; r < repetitions; ++r) {
        bytes = 0;
        const double start = cpu_seconds();
        write_generated_corpus("uniform", count, 1, [&](std::string_view piece) { bytes += piece.size(); });
        us.push_back((cpu_seconds() - start) * 1e6 / double(count));
        if (bytes == 0) throw std::logic_error("corpus generate wrote nothing");
    }
    return {median_of(us), static_cast<double>(bytes) / static_cast<double>(count)};
}

}  // namespace

std::vector<audit_target> audit_timing_targets() {
    std::vector<variant> chosen;
    for (const std::string_view name : textbook_variant_names()) chosen.push_back(*find_builtin_variant(name));
    return targets_for(chosen);
}

std::vector<std::pair<std::string, double>> audit_parts::named() const {
    return {{"targets", targets},       {"oracle", oracle},          {"verdicts", verdicts},
            {"figures", figures},       {"accumulate", accumulate},  {"stability", stability}};
}

audit_timing measure_audit_timing(const std::vector<corpus_case>& cases, int repetitions, double min_time_s,
                                  const whole_audit_pass& pass) {
    const std::vector<audit_target> targets = audit_timing_targets();
    std::map<std::string, std::vector<corpus_case>> by_family;
    for (const corpus_case& c : cases) by_family[family_key(c)].push_back(c);
    audit_timing out;
    out.target_count = targets.size();
    out.repetitions = repetitions;
    for (const auto& [family, members] : by_family) {
        fmt::print(stderr, "bench --audit: {} ({} cases)\n", family, members.size());
        out.rows.push_back(time_family(family, members, targets, repetitions, min_time_s, pass));
    }
    out.rows.push_back(time_family("all", cases, targets, repetitions, min_time_s, pass));
    out.generation = time_uniform_generation(repetitions, 20000);
    return out;
}

}  // namespace rayverify::bench
