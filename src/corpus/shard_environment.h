// `--shard auto`: which shard this process is, read from the environment the
// batch system started it in, so that one command line serves every task of a
// job array.
//
//   Slurm job array     SLURM_ARRAY_TASK_ID with SLURM_ARRAY_TASK_MIN/_MAX
//                       (and _STEP) or, alone, _COUNT (ids then 0 … COUNT − 1)
//   Kubernetes          JOB_COMPLETION_INDEX (0-based); the count is not in
//   Indexed Job         the pod's environment: `--shard auto/N`, N = completions
//   any launcher        RAYVERIFY_SHARD_INDEX (0-based) and
//                       RAYVERIFY_TOTAL_SHARDS, as GoogleTest's GTEST_SHARD_*
//
// Every source that is set must name the same shard (and `auto/N` the same N);
// none set, a malformed value or a disagreement is an input_error naming the
// variables and their values.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "corpus/case_stream.h"

namespace rayverify {

// Looks a variable up: nullopt when unset. Tests pass a map.
using environment_lookup = std::function<std::optional<std::string>(const std::string& name)>;

// The process's own environment (getenv).
environment_lookup process_environment();

struct resolved_shard {
    shard_spec shard;
    std::string origin;  // where K and N came from ("--shard 2/4", or the variables read)
};

// `text` is "K/N", "auto" or "auto/N"; throws input_error (field "--shard").
resolved_shard resolve_shard(std::string_view text, const environment_lookup& environment);

}  // namespace rayverify
