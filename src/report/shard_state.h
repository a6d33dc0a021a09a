// The state of an audit run: its accumulators (compare/audit, compare/stability)
// and plot sample (case_points), which is everything its reports are rendered
// from. A shard (`rayverify audit --shard K/N`) saves it as JSON beside its
// report; `rayverify merge` reads the shards' states back, merges them and
// renders exactly the report one run over the whole input would have written.
// Every double is stored as a hex float, so nothing is rounded on the way.
// The file's every type has one mapping (corpus/json_mapping.h, in
// shard_state.cpp) that the audit writes, and merge reads and checks.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/case_examples.h"
#include "compare/contract_lint.h"
#include "compare/stability.h"
#include "corpus/case_stream.h"
#include "corpus/json_mapping.h"
#include "report/audit_report.h"
#include "report/stability_report.h"

namespace rayverify {

inline constexpr const char* shard_state_format = "rayverify-shard-state 5";
inline constexpr const char* shard_state_file = "shard.json";

// Everything an audit accumulates (one per thread, one per shard).
struct audit_state {
    explicit audit_state(const std::vector<audit_target>& targets);
    void merge(const audit_state& other);

    audit_accumulator audit;
    stability_accumulator stability;
    case_points points;
    contract_lint_accumulator lint;
    case_examples examples;
};

// The labels the plots and per-case lines use for the targets.
std::vector<std::string> target_labels(const std::vector<audit_target>& targets);

// The whole report.json of an audit: audit_report_json of `totals` (the
// state's audit.finish(), formed once by the caller), then "stability" (its
// statistics formed on `threads` threads), "case_points" and
// "contract_hints" (compare/contract_lint.h) and "cases_to_open" (compare/case_examples.h).
nlohmann::ordered_json audit_report_document(const audit_state& state, const audit_totals& totals,
                                             const run_context& context, unsigned threads = 1);

// The head of a shard's state file: everything but its accumulated state,
// which `rayverify merge` reads first and checks the shards against each other by.
struct shard_header {
    struct digests_record {
        std::optional<std::string> results;  // a results file's (and its companion's) contents; none: null
        std::vector<std::string> plugins;    // each plugin library's
    };
    struct input_record {
        std::vector<std::string> paths, generated;
        std::size_t cases = 0;  // the whole input's
        std::string fingerprint;
        digests_record digests;
    };

    std::size_t schema_version = 0;
    std::string format;
    nlohmann::ordered_json build;  // build_json(), compared as a whole
    std::string command;
    input_record input;
    shard_spec shard;
    std::size_t cases = 0;  // the cases this shard audited ("shard.cases")
    std::vector<audit_target> targets;
    // The per-case file, relative to the shard directory, and the digest of its
    // contents as the audit wrote them; both null when the shard wrote none.
    std::optional<std::string> per_case_file, per_case_digest;
};

// The input's digests' mapping (also what merge compares two shards' digests by).
void map_json(json_io& io, shard_header::digests_record& digests);

// The header's one mapping: written by the audit, read and checked by merge
// (the format first, then the type and range of every field: 1 ≤ index ≤
// count, fingerprints and digests of 16 hex digits, a per-case file inside
// the shard directory).
void map_json(json_io& io, shard_header& header);

// A shard's state file: the header, then "state" (last, so that merge can
// read the headers of many shards without their states).
nlohmann::ordered_json shard_document(const shard_header& header, const audit_state& state);

// A shard's state file parsed: whole (read into memory first: parsing from a
// string is faster than from a stream), or (`header_only`) up to its "state",
// which is not read. Throws input_error naming the file when it cannot be
// read or is not JSON (a FIFO or a device is refused before it is opened).
nlohmann::ordered_json read_shard_document(const std::filesystem::path& file, bool header_only);

// The header of a shard's state document (whole, or without "state").
// Throws input_error(file, 0, FIELD, problem).
shard_header read_shard_header(const nlohmann::ordered_json& doc, const std::string& file);

// The state of a shard's document whose header is `header`, checked field by
// field and for the consistency of its figures (counts that add up over
// verdicts, families and histogram buckets; maxima in their histogram's last
// bucket; the whole run's tallies equal to the families' merge; case indices
// inside the input and the shard). Throws input_error(file, 0, FIELD,
// problem), FIELD a path such as "state.audit.overall[0].verdicts[1] (false_miss)".
audit_state read_shard_state(const nlohmann::ordered_json& doc, const std::string& file, const shard_header& header);

}  // namespace rayverify
