// The version of each JSON and JSON Lines format rayverify writes, carried in
// every object as "schema_version". Raised when a field is removed, renamed
// or changes meaning; fields may be added without raising it
// (docs/versioning.md). docs/schema/<name>.schema.json describes each, and
// tests/schema_test.cpp checks real outputs against them.
#pragma once

namespace rayverify::schema_version {

inline constexpr int report = 2;        // report.json of audit, bench and merge (report.schema.json)
inline constexpr int per_case = 2;      // each --per-case line (per-case.schema.json)
inline constexpr int shard_state = 1;   // shard.json of audit --shard (shard-state.schema.json)
inline constexpr int scene_report = 2;  // scene_report.json of audit --scene (scene-report.schema.json)
inline constexpr int variants = 1;      // variants --json (variants.schema.json)
inline constexpr int benchmark = 1;     // bench --benchmark-json, Google Benchmark's format (benchmark.schema.json)

}  // namespace rayverify::schema_version
