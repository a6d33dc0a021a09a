#include "corpus/shard_environment.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include "core/input_error.h"

namespace rayverify {

namespace {

input_error shard_error(const std::string& message) { return input_error("", 0, "--shard", message); }

// What one source says: a 0-based index and, when it knows it, the count.
struct shard_claim {
    std::string source;  // the variables it read, with their values
    std::size_t index = 0;
    std::optional<std::size_t> count;
};

class environment_reader {
public:
    explicit environment_reader(const environment_lookup& lookup) : lookup_(lookup) {}

    bool has(const std::string& name) const { return lookup_(name).has_value(); }

    // The variable as a whole number; nullopt when unset.
    std::optional<std::size_t> number(const std::string& name) {
        const std::optional<std::string> text = lookup_(name);
        if (!text) return std::nullopt;
        std::size_t value = 0;
        if (!parse_unsigned(*text, value))
            throw shard_error(fmt::format("--shard auto: {}='{}' is not a whole number", name, *text));
        read_ += fmt::format("{}{}={}", read_.empty() ? "" : " ", name, *text);
        return value;
    }

    // The variables read since the last call, as "NAME=value ...".
    std::string take_read() { return std::exchange(read_, {}); }

private:
    const environment_lookup& lookup_;
    std::string read_;
};

// Slurm numbers an array's tasks by --array=MIN-MAX[:STEP]; task K of N is the
// K-th id of that range. A list of ids (--array=1,5,9) has no such order.
std::optional<shard_claim> slurm_claim(environment_reader& env) {
    const std::optional<std::size_t> id = env.number("SLURM_ARRAY_TASK_ID");
    if (!id) return std::nullopt;
    const std::optional<std::size_t> min = env.number("SLURM_ARRAY_TASK_MIN");
    const std::optional<std::size_t> max = env.number("SLURM_ARRAY_TASK_MAX");
    const std::optional<std::size_t> step = env.number("SLURM_ARRAY_TASK_STEP");
    const std::optional<std::size_t> count = env.number("SLURM_ARRAY_TASK_COUNT");
    shard_claim claim{"Slurm job array (" + env.take_read() + ")", 0, {}};
    const auto bad = [&](const std::string& why) {
        return shard_error(fmt::format("--shard auto: {}: {}", claim.source, why));
    };
    if (min && max) {
        const std::size_t s = step.value_or(1);
        if (s == 0 || *max < *min || *id < *min || *id > *max || (*id - *min) % s != 0)
            throw bad("the task id is not in the range MIN-MAX:STEP");
        claim.index = (*id - *min) / s;
        claim.count = (*max - *min) / s + 1;
        if (count && *count != *claim.count)
            throw bad(fmt::format("{} tasks, but MIN-MAX:STEP has {}: give the array as one range, "
                                  "e.g. sbatch --array=1-{}",
                                  *count, *claim.count, *count));
        return claim;
    }
    if (min || max) throw bad("SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX come together");
    if (!count) throw bad("neither SLURM_ARRAY_TASK_MIN/MAX nor SLURM_ARRAY_TASK_COUNT is set");
    if (*id >= *count)
        throw bad("without SLURM_ARRAY_TASK_MIN the task ids are taken as 0 to COUNT-1, and this one is not");
    claim.index = *id;
    claim.count = *count;
    return claim;
}

std::optional<shard_claim> kubernetes_claim(environment_reader& env) {
    const std::optional<std::size_t> index = env.number("JOB_COMPLETION_INDEX");
    if (!index) return std::nullopt;
    return shard_claim{"Kubernetes Indexed Job (" + env.take_read() + ")", *index, {}};
}

std::optional<shard_claim> rayverify_claim(environment_reader& env) {
    const std::optional<std::size_t> index = env.number("RAYVERIFY_SHARD_INDEX");
    const std::optional<std::size_t> total = env.number("RAYVERIFY_TOTAL_SHARDS");
    const std::string source = env.take_read();
    if (!index && !total) return std::nullopt;
    if (!index) throw shard_error(fmt::format("--shard auto: {} without RAYVERIFY_SHARD_INDEX", source));
    return shard_claim{source, *index, total};
}

std::string claim_text(const shard_claim& c) {
    return c.count ? fmt::format("{}/{}", c.index + 1, *c.count) : fmt::format("{}/?", c.index + 1);
}

// Every claim must name one shard; an explicit N (auto/N) must match every count.
resolved_shard combine(const std::vector<shard_claim>& claims, std::optional<std::size_t> explicit_count,
                       const std::string& text) {
    std::optional<std::size_t> count = explicit_count;
    for (const shard_claim& c : claims)
        if (!count) count = c.count;
    if (!count)
        throw shard_error(fmt::format("--shard {}: {} gives the shard's index, not the number of shards: use "
                                      "--shard auto/N (for a Kubernetes Indexed Job, N = spec.completions)",
                                      text, claims.front().source));
    std::string sources, says;
    bool agree = true;
    for (const shard_claim& c : claims) {
        agree = agree && c.index == claims.front().index && c.count.value_or(*count) == *count;
        sources += (sources.empty() ? "" : "; ") + c.source;
        says += fmt::format("{}{} says {}", says.empty() ? "" : ", ", c.source, claim_text(c));
    }
    if (!agree) {
        if (explicit_count) says += fmt::format(", --shard {} says N = {}", text, *explicit_count);
        throw shard_error(fmt::format("--shard {}: the environment names different shards: {}", text, says));
    }
    const std::size_t index = claims.front().index;
    if (index >= *count)
        throw shard_error(fmt::format("--shard {}: {} is index {} (0-based), beyond {} shards", text, sources, index,
                                      *count));
    resolved_shard r;
    r.shard = {index + 1, *count};
    r.origin = fmt::format("--shard {}: shard {} from {}", text, r.shard.text(), sources);
    return r;
}

}  // namespace

environment_lookup process_environment() {
    return [](const std::string& name) -> std::optional<std::string> {
        const char* value = std::getenv(name.c_str());
        if (value == nullptr) return std::nullopt;
        return std::string(value);
    };
}

resolved_shard resolve_shard(std::string_view text, const environment_lookup& environment) {
    if (text != "auto" && !text.starts_with("auto/")) return {parse_shard(text), fmt::format("--shard {}", text)};
    const std::string spelled(text);
    std::optional<std::size_t> explicit_count;
    if (text != "auto") {
        std::size_t n = 0;
        if (!parse_unsigned(text.substr(5), n) || n == 0)
            throw shard_error(fmt::format("'{}' is not auto/N with N >= 1 (N: the number of shards)", text));
        explicit_count = n;
    }
    environment_reader env(environment);
    std::vector<shard_claim> claims;
    for (auto claim : {slurm_claim(env), kubernetes_claim(env), rayverify_claim(env)})
        if (claim) claims.push_back(std::move(*claim));
    if (claims.empty()) {
        std::string hint;
        if (env.has("SLURM_JOB_ID")) hint = " (SLURM_JOB_ID is set: submit the job as an array, sbatch --array=1-N)";
        throw shard_error(fmt::format(
            "--shard {}: no shard in the environment{}: none of SLURM_ARRAY_TASK_ID (Slurm job array), "
            "JOB_COMPLETION_INDEX (Kubernetes Indexed Job, with --shard auto/N) or RAYVERIFY_SHARD_INDEX and "
            "RAYVERIFY_TOTAL_SHARDS is set; or give the shard as --shard K/N",
            spelled, hint));
    }
    return combine(claims, explicit_count, spelled);
}

}  // namespace rayverify
