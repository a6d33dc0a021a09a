// Rendering of the stability figures, the timings and the per-case points the
// plots draw, as JSON sections added beside the existing report.json fields.
// Rendering only: the figures come from compare/stability and bench/timing.
#pragma once

#include <nlohmann/json.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench/timing.h"
#include "compare/audit.h"
#include "report/json_line.h"
#include "compare/stability.h"

namespace rayverify {

// report["stability"]: definitions, then per target the condition buckets,
// the causes of its disagreements and the stable/unstable call, overall and
// per family. `precision_labels` overrides the precision name per target
// (e.g. "long double"); empty means precision_name(target.prec).
nlohmann::ordered_json stability_json(const audit_totals& totals, const stability_totals& stability,
                                      const std::vector<std::string>& precision_labels = {});

// A case's stability measures per precision in use, as the value of a
// per-case line's "stability" (per_case_line carries each result's verdict and cause).
void write_stability_measures(json_line& out, const case_stability& s);

// Column-oriented per-case values for the plots: family, distance ratio,
// κ at float and double, and per target label the verdict, near-root ulps
// and a disagreement's cause.
// A bounded, deterministic sample: per family, the `per_family` cases with the
// smallest hash of their id (ties: smallest global index), listed in input
// order; every case when a family has no more. Mergeable like the
// accumulators (one per thread or shard); the shard state lists its rows
// (for_each_in_key_order) and inserts them back.
class case_points {
public:
    static constexpr std::size_t per_family = 1024;

    // One kept case, in plain values (turned into JSON only by to_json and
    // the shard state): a row is built for every case a family keeps.
    struct row {
        std::size_t index = 0;
        std::string family;
        std::optional<double> ratio, kappa_float, kappa_double;  // absent: null in the report
        // What the plots draw of one target's answer.
        struct target_point {
            verdict_kind verdict = verdict_kind::agree;
            std::optional<double> near_ulp;           // an agreeing target's near-root ulps
            std::optional<disagreement_cause> cause;  // a disagreeing target's cause
        };
        // Aligned with the targets: one allocation per row (three columns of
        // their own were three, in every case of a family of ≤ 1024).
        std::vector<target_point> per_target;
    };
    using sample_key = std::pair<std::uint64_t, std::size_t>;  // (hash of id, global index)

    case_points(std::vector<audit_target> targets, std::vector<std::string> labels);
    void add(const audited_case& c, std::size_t index);
    void insert(const std::string& family, const sample_key& key, row r);
    // Whether insert would keep a row with this key (cheap: no row needed).
    bool would_keep(const std::string& family, const sample_key& key) const;
    void merge(const case_points& other);
    nlohmann::ordered_json to_json() const;

    // visit(family, key, row) for every kept row, by family, then by key
    // (the order the shard state lists them in).
    void for_each_in_key_order(
        const std::function<void(const std::string& family, const sample_key& key, const row& r)>& visit) const;

private:
    // A family's kept rows as a max-heap by key: the largest, the first to
    // leave, on top. Keeping a case costs a sift; a tree of up to 1024 nodes
    // cost a walk from node to node, each a load that missed the cache.
    using kept_rows = std::vector<std::pair<sample_key, row>>;
    std::vector<audit_target> targets_;
    std::vector<std::string> labels_;
    std::map<std::string, kept_rows> sample_;  // family → kept rows
};

// report["timing"]: every row, the reference and each row's ratio to the
// reference measured in the same family and run, plus per-target totals
// (case-weighted over the families: ns for one pass over all the cases).
nlohmann::ordered_json timing_json(const std::vector<bench::timing_row>& rows, const bench::timing_options& options,
                                   const std::string& reference_label);

}  // namespace rayverify
