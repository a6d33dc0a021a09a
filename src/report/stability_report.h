// Rendering of the stability figures, the timings and the per-case points the
// plots draw, as JSON sections added beside the existing report.json fields.
// Rendering only: the figures come from compare/stability and bench/timing.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/timing.h"
#include "compare/audit.h"
#include "compare/stability.h"

namespace rayverify {

// report["stability"]: definitions, then per target the condition buckets,
// the causes of its disagreements and the stable/unstable call, overall and
// per family. `precision_labels` overrides the precision name per target
// (e.g. "long double"); empty means precision_name(target.prec).
nlohmann::ordered_json stability_json(const audit_totals& totals, const stability_totals& stability,
                                      const std::vector<std::string>& precision_labels = {});

// Adds "stability" (per precision in use) and a "cause" per disagreeing
// result to one per-case JSON object built by per_case_json.
void add_stability_fields(nlohmann::ordered_json& line, const case_stability& s,
                          const std::vector<audit_target>& targets);

// Column-oriented per-case values for the plots: family, distance ratio,
// κ at float and double, and per target label the verdict and near-root ulps.
class case_points {
public:
    case_points(std::vector<audit_target> targets, std::vector<std::string> labels);
    void add(const audited_case& c, const case_stability& s);
    nlohmann::ordered_json to_json() const;

private:
    std::vector<audit_target> targets_;
    std::vector<std::string> labels_;
    nlohmann::ordered_json family_ = nlohmann::ordered_json::array(), ratio_ = nlohmann::ordered_json::array(),
                           kappa_float_ = nlohmann::ordered_json::array(),
                           kappa_double_ = nlohmann::ordered_json::array();
    std::vector<nlohmann::ordered_json> verdict_, near_ulp_;
};

// report["timing"]: every row, the reference and each row's ratio to the
// reference measured in the same family and run, plus per-target totals
// (case-weighted over the families: ns for one pass over all the cases).
nlohmann::ordered_json timing_json(const std::vector<bench::timing_row>& rows, const bench::timing_options& options,
                                   const std::string& reference_label);

}  // namespace rayverify
