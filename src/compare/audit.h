// The audit: every case through the exact oracle and every target variant,
// judged and tallied. Pure computation; reports render what this produces.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <boost/container/flat_map.hpp>

#include "compare/error_figures.h"
#include "compare/judge.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {

// Every variant of `variants` in each precision it runs in, float first.
std::vector<audit_target> targets_for(std::span<const variant> variants);

struct audited_case {
    const corpus_case* source = nullptr;
    exact_solution exact_double;                 // for the double inputs
    std::optional<exact_solution> exact_float;   // for the float-rounded inputs (when a target runs in float)
    std::vector<target_outcome> outcomes;        // aligned with the targets
    // The stability measures at each precision in use: formed once, by the
    // case's frame at that precision (compare/judge.h), which every target's
    // judgement shared.
    case_stability stability;

    const exact_solution& exact_for(precision p) const {
        return p == precision::binary32 ? *exact_float : exact_double;
    }

    // Target t's figures to every digit (exact_figures of outcomes[t];
    // `target` is the audit's t-th, the one the outcome was judged for). A
    // tally reads a figure kept to its printed digits exactly only where a
    // maximum or a printed digit needs it; the target is then judged again
    // once for all its figures and all the tallies that ask in this case
    // (the audit's and the stability tallies, the plot sample, the
    // examples, the per-case line), not once per tally. The cache is the
    // case's: audit_case_into empties it, and an audited case is read by one
    // thread at a time (its worker, or the ordered hook between chunks). The
    // reference holds until another target's figures are asked for.
    const case_score& every_digit(std::size_t t, const audit_target& target) const;

private:
    friend void audit_case_into(audited_case&, const corpus_case&, std::span<const audit_target>,
                                std::span<const given_answer>, const figure_request&, oracle_route);
    // (target index, its figures to every digit), in the order first asked for.
    mutable std::vector<std::pair<std::size_t, case_score>> every_digit_;
};

// Every target judged on the case: the oracle once per precision in use,
// one case_frame per precision shared by the targets. `given`: empty, or one
// entry per target (an answer computed ahead by a batch call, or monostate).
// `wanted`: the figures measured, every one unless asked otherwise
// (`bench --audit` times the verdicts alone, to tell the figures' share).
// `route`: the oracle's route (oracle/oracle.h), the filtered one unless the
// reference route is asked for, to show that it gives the same audit.
audited_case audit_case(const corpus_case& c, std::span<const audit_target> targets,
                        std::span<const given_answer> given = {}, const figure_request& wanted = {},
                        oracle_route route = oracle_route::filtered);
// The same into `out`, whose storage (the outcomes' vector) is reused:
// the audit's workers judge case after case into one audited_case each.
void audit_case_into(audited_case& out, const corpus_case& c, std::span<const audit_target> targets,
                     std::span<const given_answer> given = {}, const figure_request& wanted = {},
                     oracle_route route = oracle_route::filtered);

// The answers of the targets that have a batch function (variant::batch_*)
// on `cases`, each target called once for all the cases it runs on:
// result[i][t] for case i and target t (monostate where a target has no batch
// function or does not run the case). Empty when no target has one.
std::vector<std::vector<given_answer>> batch_answers(std::span<const corpus_case> cases,
                                                     std::span<const audit_target> targets);

// The figures of a set of errors: count, exact maximum and the case attaining
// it, and the p99 and median as upper bounds (see error_summary).
struct error_statistics {
    std::size_t count = 0;
    double max = 0, p99 = 0, median = 0;
    std::string max_case;  // id of the case with the largest error
};

// A bounded, mergeable summary of non-negative errors (ULPs, bits, excess):
// the count, the exact maximum with the case attaining it (ties go to the
// smallest global case index), and a histogram over logarithmic buckets.
// A bucket holds the doubles sharing their exponent and top `resolution_bits`
// significand bits, so its upper edge exceeds every value in it by less than
// a factor 1 + 2^-resolution_bits; 0, +inf and NaN have buckets of their own.
// Quantiles are nearest-rank, reported as the upper edge of the bucket holding
// that rank, or as the maximum when it lies in the maximum's bucket: an upper
// bound of the exact nearest-rank value, within that factor, and exact when 0.
// Memory does not grow with the count (at most 2^11 binades of
// 2^resolution_bits buckets, in practice a few dozen binades), and merging summaries of disjoint sets
// of cases, in any order, gives exactly the summary of their union.
struct error_summary {
    static constexpr int resolution_bits = 7;

    std::size_t count = 0;
    double max = 0;
    std::size_t max_index = 0;  // global index of the case attaining max
    std::string max_id;
    using histogram_map = boost::container::flat_map<std::uint64_t, std::size_t>;

    void add(double error, std::size_t index, const std::string& id);
    // The same of an error known to lie in [lower, upper] (bounds_in_one_bucket
    // holds: one bucket; lower == upper: the error itself); `exact()` gives
    // the error, asked for only where the bounds leave open whether it takes
    // the maximum.
    template <class Exact>
    void add_bounded(double lower, double upper, std::size_t index, const std::string& id, Exact exact);
    void merge(const error_summary& other);
    // bucket key → number of errors in it, sorted by key.
    const histogram_map& histogram() const;
    // Adds n errors to a bucket (reading a histogram back), one of bucket_of's
    // keys: at most bucket_of(+inf).
    void add_to_bucket(std::uint64_t bucket, std::size_t n);
    error_statistics statistics() const;
    // How many errors are at least `threshold` (+inf and NaN included): exact
    // when `threshold` is a power of two, the lower edge of a bucket.
    std::size_t count_at_least(double threshold) const;
    // Nearest-rank q-quantile (0 < q ≤ 1) as the upper bound described above.
    double quantile(double q) const;
    // The same for several, in ascending order, in one walk of the histogram.
    void quantiles(std::span<const double> qs, std::span<double> bounds) const;

    static std::uint64_t bucket_of(double error);
    static double upper_edge(std::uint64_t bucket);
    // Whether `value` at global index `index` takes the maximum `max` held at
    // `max_index`: the larger error wins; on equal errors the smaller index.
    static bool takes_max(double value, std::size_t index, double max, std::size_t max_index) {
        const std::uint64_t a = std::bit_cast<std::uint64_t>(std::fabs(value)),
                            b = std::bit_cast<std::uint64_t>(std::fabs(max));
        return a != b ? a > b : index < max_index;
    }

private:
    // add() runs for every error of every target: the counts live in dense
    // blocks of 2^resolution_bits counters, one block per binade (exponent)
    // in use, found through a directory over the binades between the
    // smallest and the largest in use; an add is two loads and an increment,
    // and the histogram is read in key order without sorting. An audit's
    // figures fill a few dozen neighbouring binades, each about half full,
    // which this holds in about half the memory of a hash table of the
    // buckets. Exact zeros, the commonest error by far (a correctly rounded
    // root), are counted apart.
    static constexpr std::size_t block_size = std::size_t{1} << resolution_bits;
    static constexpr std::uint32_t no_block = ~std::uint32_t{0};
    void count_in(std::uint64_t bucket, std::size_t n);
    // Where in counts_ a bucket (not 0) is counted, when its binade has a block.
    std::optional<std::size_t> counter_of(std::uint64_t bucket) const;
    // The index in counts_ of `binade`'s first counter, its block made (zeros) when it has none.
    std::size_t block_for(std::uint32_t binade);
    // Adds n to counter i, its count beyond a byte carried into its block's carries.
    void add_to_counter(std::size_t i, std::uint64_t n);
    // Adds `carry` 256s to counter i's carries (out of line: one add in 256 at most).
    [[gnu::noinline]] void carry_into(std::size_t i, std::uint64_t carry);
    // visit(i, n) for each counter i of `block` whose whole count n (its
    // byte and its carries) is not 0, in order, while visit returns true
    // (false when it stopped the walk).
    // Eight counters at a time where the block has no carries: most are 0.
    template <class Visit>
    bool for_each_counter_of(std::uint32_t block, Visit visit) const;
    // visit(bucket, n) for each bucket holding n > 0 errors, in key order,
    // while visit returns true: what the histogram holds, without building
    // it (a summary's statistics walk it once, as far as the p99).
    template <class Visit>
    void for_each_bucket(Visit visit) const;
    // The counters are one byte wide, the count above it (in units of 256)
    // kept in a block of carries of their own, made when one of the block's
    // counters first passes 255. Every case adds a few hundred figures to
    // a few hundred histograms: their counters, a few megabytes at four
    // bytes each, did not stay in the core's cache, and counting them was
    // an eighth of an audit (20,000 `uniform` cases, the 28 textbook
    // targets). A byte each cut that time by about a third; a short audit
    // also touches fewer fresh pages.
    static constexpr int counter_bits = 8;
    std::vector<std::uint8_t> counts_;      // block_size counters per block, blocks in order of first use
    std::vector<std::uint32_t> carry_block_of_;  // block → its block of carries in carries_, or no_block (none yet)
    std::vector<std::uint64_t> carries_;    // block_size counts of 256 per block of carries
    std::vector<std::uint32_t> block_of_;  // binade − first_binade_ → its block, or no_block
    std::uint32_t first_binade_ = 0;
    std::size_t zeros_ = 0;                // errors in bucket 0 (exact zeros), kept out of the blocks
    mutable histogram_map sorted_;
    mutable bool sorted_current_ = true;
};

// Whether every value in [lower, upper] falls in one error_summary bucket:
// then a figure known only to lie there is counted in its exact value's
// bucket, and lies on its exact value's side of every threshold at the lower
// edge of a bucket (a power of two, as agree_far_fraction). The judge takes
// a figure from the oracle's enclosures where this holds
// (figure_request::root_errors::to_printed_digits).
bool bounds_in_one_bucket(double lower, double upper);

template <class Exact>
void error_summary::add_bounded(double lower, double upper, std::size_t index, const std::string& id, Exact exact) {
    // Bounds that meet are the error itself (NaN too: no bracket holds one).
    if (lower == upper || (std::isnan(lower) && std::isnan(upper))) return add(lower, index, id);
    // It cannot take the maximum where even its upper bound would not: the
    // maximum stays the exact value of the case attaining it.
    if (count == 0 || takes_max(upper, index, max, max_index)) return add(exact(), index, id);
    ++count;
    count_in(bucket_of(lower), 1);
}

// Runs job(k) for every k in [0, count) on `threads` threads, the calling one
// among them, each taking the next k from a shared counter.
void run_in_parallel(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& job);

// An accumulator tallies each case under its family only (one add per
// figure); the whole run's tally of each target is the merge of the
// families', formed when asked for (targets on `threads` threads). Tally has
// merge(const Tally&); the helpers serve the audit and stability accumulators.
template <class Tally>
std::vector<Tally> merged_over_families(const std::map<std::string, std::vector<Tally>>& by_family,
                                        std::size_t target_count, unsigned threads = 1) {
    std::vector<Tally> overall(target_count);
    run_in_parallel(target_count, threads, [&](std::size_t t) {
        for (const auto& [family, per_target] : by_family)
            if (t < per_target.size()) overall[t].merge(per_target[t]);
    });
    return overall;
}

// Every tally of `overall` and `by_family` summarised (`summarise(samples)`),
// on `threads` threads; the results in the same shape.
template <class Samples, class Summarise>
auto summarised(const std::vector<Samples>& overall, const std::map<std::string, std::vector<Samples>>& by_family,
                unsigned threads, Summarise summarise) {
    using tally = decltype(summarise(overall.front()));
    std::pair<std::vector<tally>, std::map<std::string, std::vector<tally>>> out;
    out.first.resize(overall.size());
    std::vector<std::pair<const Samples*, tally*>> jobs;
    for (std::size_t t = 0; t < overall.size(); ++t) jobs.emplace_back(&overall[t], &out.first[t]);
    for (const auto& [family, per_target] : by_family) {
        std::vector<tally>& into = out.second[family];
        into.resize(per_target.size());
        for (std::size_t t = 0; t < per_target.size(); ++t) jobs.emplace_back(&per_target[t], &into[t]);
    }
    run_in_parallel(jobs.size(), threads, [&](std::size_t k) { *jobs[k].second = summarise(*jobs[k].first); });
    return out;
}

// Adds `other`'s per-family tallies to `mine`, both aligned with the same `target_count` targets.
template <class Tally>
void merge_families(std::map<std::string, std::vector<Tally>>& mine,
                    const std::map<std::string, std::vector<Tally>>& other, std::size_t target_count) {
    for (const auto& [family, per_target] : other) {
        auto& into = mine[family];
        into.resize(target_count);
        for (std::size_t t = 0; t < per_target.size(); ++t) into[t].merge(per_target[t]);
    }
}

// Tallies of one target over some cases (mergeable): verdict counts and the
// errors over the cases whose verdict is agree.
struct target_samples {
    std::size_t cases = 0;
    std::array<std::size_t, verdict_kind_count> verdicts{};
    std::array<std::size_t, disagreement_cause_count> causes{};  // of the disagreements
    per_error_figure<error_summary> errors;  // over the agreeing cases
    void merge(const target_samples& other);
};

// Everything tallied for one target over a set of cases.
struct target_tally {
    std::size_t cases = 0;
    std::array<std::size_t, verdict_kind_count> verdicts{};
    std::array<std::size_t, disagreement_cause_count> causes{};  // of the disagreements
    // Errors over the cases whose verdict is agree (disagreements are counted above).
    per_error_figure<error_statistics> errors;
    // Agree but far: agreeing cases whose hit lies at least agree_far_fraction
    // of the radius from the exact one (scale_error_radius; the verdict only
    // asks which root a t stands for, so a far t can still agree).
    std::size_t agree_far = 0;
    std::size_t disagreements() const;
    std::size_t by_design() const;  // disagreements with a by-design cause
    // Cases judged: agreeing or disagreeing (not invalid, not breaking the contract).
    std::size_t scored() const;
    // Cases were audited and none was judged: the target passed nothing (a
    // finding of audit, a failure of the gate).
    bool scored_nothing() const { return cases > 0 && scored() == 0; }
};

// The "agree but far" line: |t − t*|·|d| ≥ 2^-10 r (about 0.1% of the radius).
inline constexpr double agree_far_fraction = 0x1p-10;
// The line in words, as every report prints it.
inline constexpr std::string_view agree_far_rule = "|t - t*|·|d| >= 2^-10 r";

// A case that is invalid in some precision: listed in reports, never scored.
struct invalid_case {
    std::string id;
    std::string source;  // "file:line"
    invalid_reason at_float = invalid_reason::none;   // none when valid there or not run in float
    invalid_reason at_double = invalid_reason::none;
    std::size_t index = 0;  // global case index (the list is kept in this order)
};

struct audit_totals {
    std::vector<audit_target> targets;
    std::size_t cases = 0;
    std::map<std::string, std::size_t> cases_by_family;
    std::vector<target_tally> overall;                             // aligned with targets
    std::map<std::string, std::vector<target_tally>> by_family;   // family → aligned with targets
    std::array<std::size_t, 2> invalid_cases{};                    // [float, double]
    std::vector<invalid_case> invalid_list;                       // every invalid case, in corpus order
};

// Accumulates audited cases in memory that does not grow with their number
// (except the list of invalid cases), then computes the statistics. Cases may
// be added in any order, by several accumulators (one per thread, one per
// shard) that are merged afterwards: the totals depend only on the set of
// (case, global index) added. The state is public so that a shard can save it.
struct audit_accumulator {
    explicit audit_accumulator(std::vector<audit_target> targets = {});
    void add(const audited_case& c, std::size_t index);
    void merge(const audit_accumulator& other);
    // The statistics (counts, maxima, quantiles read from each histogram's
    // counters in one walk), formed on `threads` threads.
    audit_totals finish(unsigned threads = 1) const;

    // The whole run's tallies of each target (aligned with targets).
    std::vector<target_samples> overall() const { return merged_over_families(by_family, targets.size()); }

    std::vector<audit_target> targets;
    std::size_t cases = 0;
    std::map<std::string, std::size_t> cases_by_family;
    std::array<std::size_t, 2> invalid{};
    std::vector<invalid_case> invalid_list;  // sorted by index
    std::map<std::string, std::vector<target_samples>> by_family;  // family → aligned with targets
};

// The family name a case is tallied under ("-" when unknown).
std::string family_key(const corpus_case& c);

// One worker's state, on cache lines of its own: a worker's accumulators
// change with every case, and two workers' sharing a line would pass it back
// and forth between their cores.
template <class T>
struct alignas(64) per_worker {
    T state;
};

// The streaming audit. `next` fills the next chunk of cases (bounded, e.g. a
// few thousand) with their global indices in the whole input and returns
// false when there are none left. Each chunk is audited on `threads` threads
// (1: the calling thread only), each with its own accumulator, merged at the
// end; a target whose variant is not thread_safe makes the whole audit run on
// the calling thread. The result is the same, bit for bit, whatever `threads`.
using case_source = std::function<bool(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices)>;

struct audit_hooks {
    // Called on a worker thread, concurrently for different cases: per-case
    // work such as stability or rendering. `slot` is the case's position in
    // its chunk, `worker` < the thread count in use. With one thread in use
    // (audit_threads) it is called in input order, on the calling thread.
    std::function<void(const audited_case&, std::size_t index, std::size_t slot, unsigned worker)> parallel;
    // Called on the calling thread for each case of a chunk, in input order,
    // after the chunk's parallel work, with the audited case: the chunk's
    // audited cases are kept until then (about 15 KB a case of 28 targets,
    // a few thousand cases, each first touched anew in a short run).
    std::function<void(const audited_case&, std::size_t index, std::size_t slot)> ordered;
    // The same without the audited case, which is then not kept: for a hook
    // that needs only what `parallel` saved by slot (a rendered line).
    std::function<void(std::size_t index, std::size_t slot)> in_order;
    // Called on the calling thread after each chunk with the cases audited so far.
    std::function<void(std::size_t done)> progress;
    // Whether a hook reads a disagreement's sentence (case_score::detail):
    // otherwise the judge leaves it unformed (figure_request::details).
    bool details = true;
};

// The thread count actually used for `targets` when `requested` are asked for.
unsigned audit_threads(const std::vector<audit_target>& targets, unsigned requested);

audit_accumulator audit_stream(const case_source& next, const std::vector<audit_target>& targets, unsigned threads,
                               const audit_hooks& hooks = {}, oracle_route route = oracle_route::filtered);

// Run the whole audit over cases in memory (global index = position). `on_case`
// sees every audited case in corpus order (for per-case output);
// `on_progress(done, total)` is called now and then.
audit_totals run_audit(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                       const std::function<void(const audited_case&)>& on_case = {},
                       const std::function<void(std::size_t, std::size_t)>& on_progress = {},
                       unsigned threads = 1);

}  // namespace rayverify
