#include "compare/audit.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <barrier>
#include <bit>
#include <cmath>
#include <cstring>
#include <exception>
#include <iterator>
#include <mutex>
#include <system_error>
#include <thread>
#include <tuple>

#include "core/case_in_progress.h"

namespace rayverify {

std::vector<audit_target> targets_for(std::span<const variant> variants) {
    std::vector<audit_target> targets;
    for (const variant& v : variants)
        for (precision p : {precision::binary32, precision::binary64})
            if (v.runs_in(p)) targets.push_back({v, p});
    return targets;
}

void audit_case_into(audited_case& out, const corpus_case& c, std::span<const audit_target> targets,
                     std::span<const given_answer> given, const figure_request& wanted, oracle_route route) {
    const case_in_progress announced(c);  // named by a plugin that crashes or hangs on it
    out.source = &c;
    out.exact_double = solve_case(c, precision::binary64, route);
    const bool float_used = std::any_of(targets.begin(), targets.end(),
                                        [](const audit_target& t) { return t.prec == precision::binary32; });
    if (float_used)
        out.exact_float = solve_case(c, precision::binary32, route);
    else
        out.exact_float.reset();
    const case_frame at_double(out.exact_double, c.geometry);
    std::optional<case_frame> at_float;
    if (float_used) at_float.emplace(*out.exact_float, target_input(precision::binary32, c));
    out.outcomes.clear();  // the outcomes' storage is kept from case to case
    out.every_digit_.clear();
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const case_frame& frame = targets[t].prec == precision::binary32 ? *at_float : at_double;
        judge_target_into(out.outcomes.emplace_back(), targets[t], c, frame,
                          given.empty() ? given_answer{} : given[t], wanted);
    }
    out.stability.at_double = at_double.stability();
    if (at_float)
        out.stability.at_float = at_float->stability();
    else
        out.stability.at_float.reset();
}

const case_score& audited_case::every_digit(std::size_t t, const audit_target& target) const {
    for (const auto& [judged, figures] : every_digit_)
        if (judged == t) return figures;
    return every_digit_.emplace_back(t, exact_figures(target, *source, outcomes[t], exact_for(target.prec))).second;
}

audited_case audit_case(const corpus_case& c, std::span<const audit_target> targets,
                        std::span<const given_answer> given, const figure_request& wanted, oracle_route route) {
    audited_case result;
    audit_case_into(result, c, targets, given, wanted, route);
    return result;
}

namespace {

template <class T>
void batch_answers_in(std::span<const corpus_case> cases, const audit_target& target, std::size_t t,
                      const std::function<void(std::span<const batch_case<T>>, std::span<answer<T>>)>& batch,
                      std::vector<std::vector<given_answer>>& out) {
    std::vector<batch_case<T>> inputs;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < cases.size(); ++i)
        if (std::optional<batch_case<T>> in = run_input<T>(target, cases[i])) {
            inputs.push_back(*in);
            which.push_back(i);
        }
    if (inputs.empty()) return;
    std::vector<answer<T>> answers(inputs.size());
    const case_in_progress announced(cases[which.front()]);  // named by a plugin that fails on the batch
    batch(inputs, answers);
    for (std::size_t k = 0; k < which.size(); ++k) out[which[k]][t] = answers[k];
}

}  // namespace

std::vector<std::vector<given_answer>> batch_answers(std::span<const corpus_case> cases,
                                                     std::span<const audit_target> targets) {
    std::vector<std::vector<given_answer>> out;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const variant& v = targets[t].subject;
        const bool batched = targets[t].prec == precision::binary32 ? static_cast<bool>(v.batch_float)
                                                                     : static_cast<bool>(v.batch_double);
        if (!batched) continue;
        if (out.empty()) out.assign(cases.size(), std::vector<given_answer>(targets.size()));
        if (targets[t].prec == precision::binary32)
            batch_answers_in<float>(cases, targets[t], t, v.batch_float, out);
        else
            batch_answers_in<double>(cases, targets[t], t, v.batch_double, out);
    }
    return out;
}

std::size_t target_tally::disagreements() const {
    std::size_t n = 0;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (is_disagreement(static_cast<verdict_kind>(k))) n += verdicts[k];
    return n;
}

std::size_t target_tally::by_design() const { return by_design_count(causes); }

std::size_t target_tally::scored() const {
    std::size_t n = 0;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (is_scored(static_cast<verdict_kind>(k))) n += verdicts[k];
    return n;
}

// Bucket keys: 0 holds exactly 0; key k ≥ 1 holds the doubles whose bits,
// shifted right by 52 − resolution_bits, equal k − 1. For non-negative
// doubles (with +inf and NaN above every finite value) the bits order as the
// values do, so keys do too.
namespace {

constexpr int bucket_shift = 52 - error_summary::resolution_bits;

std::uint64_t bits_of(double x) { return std::bit_cast<std::uint64_t>(x); }

}  // namespace

bool bounds_in_one_bucket(double lower, double upper) {
    return error_summary::bucket_of(lower) == error_summary::bucket_of(upper);
}

std::uint64_t error_summary::bucket_of(double error) {
    const double x = std::fabs(error);
    return x == 0 ? 0 : (bits_of(x) >> bucket_shift) + 1;
}

std::size_t error_summary::count_at_least(double threshold) const {
    std::size_t n = 0;
    const std::uint64_t first = bucket_of(threshold);
    for_each_bucket([&](std::uint64_t bucket, std::uint64_t count) {
        if (bucket >= first) n += count;
        return true;
    });
    return n;
}

double error_summary::upper_edge(std::uint64_t bucket) {
    if (bucket == 0) return 0;
    const double lower = std::bit_cast<double>((bucket - 1) << bucket_shift);
    if (!std::isfinite(lower)) return lower;  // +inf or NaN: a bucket of its own
    return std::bit_cast<double>(bucket << bucket_shift);
}

void error_summary::add(double error, std::size_t index, const std::string& id) {
    if (count == 0 || takes_max(error, index, max, max_index)) {
        max = error;
        max_index = index;
        max_id = id;
    }
    ++count;
    count_in(bucket_of(error), 1);
}

void error_summary::add_to_bucket(std::uint64_t bucket, std::size_t n) { count_in(bucket, n); }

std::optional<std::size_t> error_summary::counter_of(std::uint64_t bucket) const {
    const auto binade = static_cast<std::uint32_t>((bucket - 1) >> resolution_bits);
    if (binade < first_binade_ || binade - first_binade_ >= block_of_.size()) return std::nullopt;
    const std::uint32_t block = block_of_[binade - first_binade_];
    if (block == no_block) return std::nullopt;
    return block * block_size + ((bucket - 1) & (block_size - 1));
}

std::size_t error_summary::block_for(std::uint32_t binade) {
    if (block_of_.empty()) {
        // An audit's summary of 500 cases ends with about ten blocks over a
        // directory of a dozen binades (the median over the shipped uniform
        // corpus' summaries; near_tangent's, five over nine): room for the
        // first few is made at once, where growing from one reallocated and
        // copied them at each doubling.
        first_binade_ = binade;
        block_of_.reserve(16);
        counts_.reserve(4 * block_size);
        block_of_.assign(1, no_block);
    } else if (binade < first_binade_) {  // the directory extended downwards
        block_of_.insert(block_of_.begin(), first_binade_ - binade, no_block);
        first_binade_ = binade;
    } else if (binade - first_binade_ >= block_of_.size()) {  // upwards
        block_of_.resize(binade - first_binade_ + 1, no_block);
    }
    std::uint32_t& block = block_of_[binade - first_binade_];
    if (block == no_block) {
        block = static_cast<std::uint32_t>(counts_.size() / block_size);
        counts_.resize(counts_.size() + block_size, 0);
    }
    return block * block_size;
}

void error_summary::add_to_counter(std::size_t i, std::uint64_t n) {
    const std::uint64_t sum = counts_[i] + n;
    counts_[i] = static_cast<std::uint8_t>(sum);
    if (sum >> counter_bits) [[unlikely]]
        carry_into(i, sum >> counter_bits);
}

void error_summary::carry_into(std::size_t i, std::uint64_t carry) {
    const std::size_t block = i / block_size;
    if (carry_block_of_.size() <= block) carry_block_of_.resize(block + 1, no_block);
    if (carry_block_of_[block] == no_block) {
        carry_block_of_[block] = static_cast<std::uint32_t>(carries_.size() / block_size);
        carries_.resize(carries_.size() + block_size, 0);
    }
    carries_[carry_block_of_[block] * block_size + i % block_size] += carry;
}

void error_summary::count_in(std::uint64_t bucket, std::size_t n) {
    sorted_current_ = false;
    if (bucket == 0) {
        zeros_ += n;
        return;
    }
    const std::optional<std::size_t> counter = counter_of(bucket);
    add_to_counter(counter ? *counter
                           : block_for(static_cast<std::uint32_t>((bucket - 1) >> resolution_bits)) +
                                 ((bucket - 1) & (block_size - 1)),
                   n);
}

template <class Visit>
bool error_summary::for_each_counter_of(std::uint32_t block, Visit visit) const {
    static_assert(block_size % 8 == 0);
    const std::size_t first = block * block_size;
    if (block < carry_block_of_.size() && carry_block_of_[block] != no_block) {
        const std::uint64_t* carried = &carries_[carry_block_of_[block] * block_size];
        for (std::size_t i = first; i < first + block_size; ++i)
            if (const std::uint64_t n = counts_[i] + (carried[i - first] << counter_bits); n != 0 && !visit(i, n))
                return false;
        return true;
    }
    for (std::size_t k = first; k < first + block_size; k += 8) {
        std::uint64_t eight = 0;
        std::memcpy(&eight, &counts_[k], sizeof eight);
        if (eight == 0) continue;
        for (std::size_t i = k; i < k + 8; ++i)
            if (counts_[i] != 0 && !visit(i, std::uint64_t{counts_[i]})) return false;
    }
    return true;
}

template <class Visit>
void error_summary::for_each_bucket(Visit visit) const {
    if (zeros_ > 0 && !visit(std::uint64_t{0}, std::uint64_t{zeros_})) return;
    for (std::size_t d = 0; d < block_of_.size(); ++d) {
        if (block_of_[d] == no_block) continue;
        // Counter i of the block holds key first_key + (i − first).
        const std::uint64_t first_key = ((first_binade_ + d) << resolution_bits) + 1;
        const std::size_t first = block_of_[d] * block_size;
        const auto visit_bucket = [&](std::size_t i, std::uint64_t n) { return visit(first_key + (i - first), n); };
        if (!for_each_counter_of(block_of_[d], visit_bucket)) return;
    }
}

const error_summary::histogram_map& error_summary::histogram() const {
    if (sorted_current_) return sorted_;
    std::vector<std::pair<std::uint64_t, std::size_t>> entries;
    for_each_bucket([&entries](std::uint64_t bucket, std::uint64_t n) {
        entries.emplace_back(bucket, n);
        return true;
    });
    sorted_.clear();
    sorted_.insert(boost::container::ordered_unique_range, entries.begin(), entries.end());
    sorted_current_ = true;
    return sorted_;
}

void error_summary::merge(const error_summary& other) {
    if (other.count == 0) return;
    if (count == 0 || takes_max(other.max, other.max_index, max, max_index)) {
        max = other.max;
        max_index = other.max_index;
        max_id = other.max_id;
    }
    count += other.count;
    zeros_ += other.zeros_;
    sorted_current_ = false;
    if (block_of_.empty()) {  // nothing to merge into (a family's summary into a whole run's): the blocks copied
        counts_ = other.counts_;
        carry_block_of_ = other.carry_block_of_;
        carries_ = other.carries_;
        block_of_ = other.block_of_;
        first_binade_ = other.first_binade_;
        return;
    }
    for (std::size_t d = 0; d < other.block_of_.size(); ++d) {
        if (other.block_of_[d] == no_block) continue;
        const std::size_t from = other.block_of_[d] * block_size;
        const std::size_t into = block_for(other.first_binade_ + static_cast<std::uint32_t>(d));
        other.for_each_counter_of(other.block_of_[d], [&](std::size_t i, std::uint64_t n) {
            add_to_counter(into + (i - from), n);
            return true;
        });
    }
}

double error_summary::quantile(double q) const {
    double bound = 0;
    quantiles({&q, 1}, {&bound, 1});
    return bound;
}

void error_summary::quantiles(std::span<const double> qs, std::span<double> bounds) const {
    if (count == 0) {
        std::fill(bounds.begin(), bounds.end(), 0.0);
        return;
    }
    const auto rank_of = [this](double q) {
        return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(q * static_cast<double>(count))), 1, count);
    };
    std::fill(bounds.begin(), bounds.end(), max);
    if (qs.empty()) return;
    std::size_t next = 0, seen = 0, rank = rank_of(qs[0]);  // rank: qs[next]'s
    for_each_bucket([&](std::uint64_t bucket, std::uint64_t n) {
        seen += n;
        while (next < qs.size() && seen >= rank) {  // qs[next]'s rank is in this bucket
            bounds[next] = bucket == bucket_of(max) ? max : upper_edge(bucket);
            if (++next < qs.size()) rank = rank_of(qs[next]);
        }
        return next < qs.size();  // on to the next bucket while a quantile is left
    });
}

error_statistics error_summary::statistics() const {
    error_statistics stats;
    stats.count = count;
    if (count == 0) return stats;
    stats.max = max;
    stats.max_case = max_id;
    // One walk of the histogram for both (ascending, as quantiles asks).
    const double qs[] = {0.5, 0.99};
    double bounds[2];
    quantiles(qs, bounds);
    stats.median = bounds[0];
    stats.p99 = bounds[1];
    return stats;
}

void target_samples::merge(const target_samples& other) {
    cases += other.cases;
    for (int k = 0; k < verdict_kind_count; ++k) verdicts[k] += other.verdicts[k];
    for (int c = 0; c < disagreement_cause_count; ++c) causes[c] += other.causes[c];
    for (const error_figure_definition& f : error_figures) errors[f.figure].merge(other.errors[f.figure]);
}

std::string family_key(const corpus_case& c) { return c.family.empty() ? "-" : c.family; }

audit_accumulator::audit_accumulator(std::vector<audit_target> t) : targets(std::move(t)) {}

void audit_accumulator::add(const audited_case& c, std::size_t index) {
    ++cases;
    const std::string family = family_key(*c.source);
    ++cases_by_family[family];
    if (!c.exact_double.valid()) ++invalid[1];
    if (c.exact_float && !c.exact_float->valid()) ++invalid[0];
    if (!c.exact_double.valid() || (c.exact_float && !c.exact_float->valid())) {
        invalid_case entry{c.source->id, c.source->source,
                           c.exact_float ? c.exact_float->invalid : invalid_reason::none, c.exact_double.invalid,
                           index};
        // Kept sorted by index; cases usually arrive in order, so this appends.
        const auto at = std::upper_bound(invalid_list.begin(), invalid_list.end(), index,
                                         [](std::size_t i, const invalid_case& e) { return i < e.index; });
        invalid_list.insert(at, std::move(entry));
    }

    auto& family_samples = by_family[family];
    family_samples.resize(targets.size());
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        target_samples& s = family_samples[t];
        ++s.cases;
        ++s.verdicts[static_cast<int>(score.verdict)];
        if (score.cause) ++s.causes[static_cast<int>(*score.cause)];
        if (score.verdict != verdict_kind::agree) continue;
        // Figures to their printed digits (case_score::figure_upper_bounds)
        // are added by their bounds, exact ones as themselves.
        for (const error_figure_definition& f : error_figures)
            if (const std::optional<double>& e = f.of_case(score))
                s.errors[f.figure].add_bounded(*e, f.upper_of_case(score), index, c.source->id,
                                               [&] { return f.of_case(c.every_digit(t, targets[t])).value(); });
    }
}

void audit_accumulator::merge(const audit_accumulator& other) {
    cases += other.cases;
    for (const auto& [family, n] : other.cases_by_family) cases_by_family[family] += n;
    for (int p = 0; p < 2; ++p) invalid[p] += other.invalid[p];
    std::vector<invalid_case> list;
    list.reserve(invalid_list.size() + other.invalid_list.size());
    std::merge(invalid_list.begin(), invalid_list.end(), other.invalid_list.begin(), other.invalid_list.end(),
               std::back_inserter(list), [](const invalid_case& a, const invalid_case& b) { return a.index < b.index; });
    invalid_list = std::move(list);
    merge_families(by_family, other.by_family, targets.size());
}

namespace {

target_tally summarise(const target_samples& s) {
    target_tally tally;
    tally.cases = s.cases;
    tally.verdicts = s.verdicts;
    tally.causes = s.causes;
    for (const error_figure_definition& f : error_figures) tally.errors[f.figure] = s.errors[f.figure].statistics();
    tally.agree_far = s.errors[error_figure::scale_error_radius].count_at_least(agree_far_fraction);
    return tally;
}

}  // namespace

audit_totals audit_accumulator::finish(unsigned threads) const {
    audit_totals totals;
    totals.targets = targets;
    totals.cases = cases;
    totals.cases_by_family = cases_by_family;
    totals.invalid_cases = invalid;
    totals.invalid_list = invalid_list;
    std::tie(totals.overall, totals.by_family) =
        summarised(merged_over_families(by_family, targets.size(), threads), by_family, threads, summarise);
    return totals;
}

namespace {

// The first exception any of several threads met, to be rethrown on the
// calling thread (an exception leaving a thread's function would end the
// process in std::terminate, with its temporary outputs and lock left behind).
class first_failure {
public:
    void keep() {
        const std::lock_guard lock(mutex_);
        if (!failure_) failure_ = std::current_exception();
    }
    bool any() {
        const std::lock_guard lock(mutex_);
        return failure_ != nullptr;
    }
    void rethrow() {
        const std::lock_guard lock(mutex_);
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    std::mutex mutex_;
    std::exception_ptr failure_;
};

// Starts helper(w) on threads w = 1 .. wanted, as many as the system lets it
// create (a container's pid limit, a lack of memory): one that cannot be
// created is left out, never waited for, and said on stderr (once a process).
// Returns how many started.
unsigned start_helpers(std::vector<std::jthread>& helpers, unsigned wanted, const std::function<void(unsigned)>& helper) {
    for (unsigned w = 1; w <= wanted; ++w) {
        try {
            helpers.emplace_back(helper, w);
        } catch (const std::system_error& e) {
            static std::atomic<bool> said{false};  // once a process: later passes meet the same limit
            if (!said.exchange(true))
                fmt::print(stderr, "rayverify: note: could start {} of the {} threads asked for ({}): working on {}\n",
                           w, wanted + 1, e.code().message(), w);
            return w - 1;
        }
    }
    return wanted;
}

}  // namespace

void run_in_parallel(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& job) {
    std::atomic<std::size_t> next{0};
    first_failure failure;
    const auto work = [&] {
        try {
            for (std::size_t k; (k = next.fetch_add(1)) < count && !failure.any();) job(k);
        } catch (...) {
            failure.keep();
        }
    };
    {
        std::vector<std::jthread> helpers;
        start_helpers(helpers, static_cast<unsigned>(std::min<std::size_t>(threads, count)) - (count > 0 ? 1 : 0),
                      [&](unsigned) { work(); });
        work();
    }  // joined
    failure.rethrow();
}

unsigned audit_threads(const std::vector<audit_target>& targets, unsigned requested) {
    const bool shareable = std::all_of(targets.begin(), targets.end(),
                                       [](const audit_target& t) { return t.subject.thread_safe; });
    return shareable ? std::max(1u, requested) : 1u;
}

audit_accumulator audit_stream(const case_source& next, const std::vector<audit_target>& targets, unsigned threads,
                               const audit_hooks& hooks, oracle_route route) {
    threads = audit_threads(targets, threads);
    std::vector<per_worker<audit_accumulator>> accumulators(threads, {audit_accumulator(targets)});
    std::vector<corpus_case> cases, next_cases;
    std::vector<std::size_t> indices, next_indices;
    std::vector<audited_case> audited;
    std::vector<std::vector<given_answer>> ahead;  // batch calls' answers for the chunk (plugins of ABI v2)
    // Workers take small runs of the chunk's cases from a shared counter:
    // which worker audits a case changes nothing, since accumulators merge
    // exactly. Without an ordered hook each worker keeps its own audited case,
    // so its buffers are allocated and freed by one thread (freeing another
    // thread's allocations contends on malloc's arenas).
    constexpr std::size_t grain = 8;
    std::atomic<std::size_t> claimed{0};
    figure_request wanted = figure_request::audit();
    wanted.details = hooks.details;
    const auto work = [&](unsigned worker) {
        audited_case own;
        for (std::size_t begin; (begin = claimed.fetch_add(grain)) < cases.size();)
            for (std::size_t i = begin; i < std::min(begin + grain, cases.size()); ++i) {
                audited_case& c = hooks.ordered ? audited[i] : own;
                audit_case_into(c, cases[i], targets, ahead.empty() ? std::span<const given_answer>{} : ahead[i],
                                wanted, route);
                accumulators[worker].state.add(c, indices[i]);
                if (hooks.parallel) hooks.parallel(c, indices[i], i, worker);
            }
    };

    // The helper threads live for the whole stream and meet the calling
    // thread at a barrier before and after each chunk. The calling thread
    // reads the following chunk while the helpers start on this one (then
    // joins them), and runs the ordered hook between chunks. Only plugins
    // may throw during the work (they force one thread, so no helper waits then).
    // A helper's exception (std::bad_alloc, a hook's) is kept and rethrown
    // here once the chunk is done; a helper that cannot be started is left
    // out of the barrier rather than waited for.
    std::barrier chunk_sync(static_cast<std::ptrdiff_t>(threads));
    bool finished = false;
    first_failure helper_failure;
    std::vector<std::jthread> helpers;
    const unsigned started = start_helpers(helpers, threads - 1, [&](unsigned w) {
        for (;;) {
            chunk_sync.arrive_and_wait();  // a chunk is ready, or the stream ended
            if (finished) return;
            try {
                work(w);
            } catch (...) {
                helper_failure.keep();
            }
            chunk_sync.arrive_and_wait();  // the chunk is done
        }
    });
    for (unsigned missing = started + 1; missing < threads; ++missing) (void)chunk_sync.arrive_and_drop();
    std::size_t done = 0;
    std::exception_ptr failure;
    const auto read_next = [&] {
        next_cases.clear();
        next_indices.clear();
        return next(next_cases, next_indices);
    };
    try {
        bool more = read_next();
        while (more) {
            std::swap(cases, next_cases);
            std::swap(indices, next_indices);
            if (cases.empty()) {
                more = read_next();
                continue;
            }
            audited.resize(hooks.ordered ? cases.size() : 0);
            claimed = 0;
            try {
                // Before the helpers start on the chunk: the answers asked of outside targets and batch calls.
                for (const audit_target& t : targets)
                    if (t.answer_chunk) t.answer_chunk(cases);
                ahead = batch_answers(cases, targets);
            } catch (...) {
                failure = std::current_exception();
                break;
            }
            if (threads > 1) chunk_sync.arrive_and_wait();
            // A chunk that cannot be read fails the run once this one is done.
            std::exception_ptr read_failure;
            try {
                more = read_next();
            } catch (...) {
                read_failure = std::current_exception();
                more = false;
            }
            try {
                work(0);
            } catch (...) {
                failure = std::current_exception();
            }
            if (threads > 1) chunk_sync.arrive_and_wait();  // even after a failure: the helpers finish the chunk
            if (!failure && helper_failure.any()) {
                try {
                    helper_failure.rethrow();
                } catch (...) {
                    failure = std::current_exception();
                }
            }
            if (failure) break;
            for (std::size_t i = 0; i < cases.size(); ++i) {
                if (hooks.ordered) hooks.ordered(audited[i], indices[i], i);
                if (hooks.in_order) hooks.in_order(indices[i], i);
            }
            done += cases.size();
            if (hooks.progress) hooks.progress(done);
            if (read_failure) {
                failure = read_failure;
                break;
            }
        }
    } catch (...) {  // from next() or a hook, between chunks: the helpers wait for a chunk
        failure = std::current_exception();
    }
    finished = true;
    if (threads > 1) chunk_sync.arrive_and_wait();
    helpers.clear();  // joined
    if (failure) std::rethrow_exception(failure);
    for (unsigned w = 1; w < threads; ++w) accumulators[0].state.merge(accumulators[w].state);
    return std::move(accumulators[0].state);
}

audit_totals run_audit(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                       const std::function<void(const audited_case&)>& on_case,
                       const std::function<void(std::size_t, std::size_t)>& on_progress, unsigned threads) {
    constexpr std::size_t chunk = 4096;
    std::size_t position = 0;
    const case_source next = [&](std::vector<corpus_case>& out, std::vector<std::size_t>& indices) {
        if (position >= cases.size()) return false;
        const std::size_t end = std::min(cases.size(), position + chunk);
        out.assign(cases.begin() + static_cast<std::ptrdiff_t>(position), cases.begin() + static_cast<std::ptrdiff_t>(end));
        for (std::size_t i = position; i < end; ++i) indices.push_back(i);
        position = end;
        return true;
    };
    audit_hooks hooks;
    // on_case sees the caller's own corpus_case objects, so that it may keep pointers to them.
    if (on_case)
        hooks.ordered = [&](const audited_case& c, std::size_t index, std::size_t) {
            audited_case own = c;
            own.source = &cases[index];
            on_case(own);
        };
    if (on_progress) hooks.progress = [&](std::size_t done) { on_progress(done, cases.size()); };
    return audit_stream(next, targets, threads, hooks).finish();
}

}  // namespace rayverify
