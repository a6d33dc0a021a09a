#!/usr/bin/env bash
# Peak memory of `audit --scene` and `render` against the scene's resolution.
# The scene is corpus/scenes/ground_sphere.json (two spheres, a light, shadow
# rays) with reflection rays added, at each N × N given (default 256 1024 4096).
# Prints one row per command and resolution: rays, wall seconds, peak RSS.
#   tools/scene_memory_benchmark.sh [N ...]      (RAYVERIFY=path/to/rayverify)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
rayverify="${RAYVERIFY:-$here/build/rayverify}"
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(256 1024 4096)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Runs a command, prints "seconds peak_rss_mib" (the child's, from getrusage).
measure() {
    /usr/bin/python3 - "$@" <<'PY'
import resource, subprocess, sys, time
start = time.monotonic()
done = subprocess.run(sys.argv[1:], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
seconds = time.monotonic() - start
if done.returncode not in (0, 1):
    sys.stderr.write(done.stdout)
    sys.exit(done.returncode)
print(f"{seconds:.1f} {resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024:.1f}")
PY
}

printf '%-8s %-11s %12s %10s %14s\n' command resolution pixels seconds "peak RSS MiB"
for n in "${sizes[@]}"; do
    /usr/bin/python3 - "$here/corpus/scenes/ground_sphere.json" "$n" > "$work/scene_$n.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
n = int(sys.argv[2])
scene["camera"]["resolution"] = [n, n]
scene["rays"]["secondary"] = {"direction": "reflect", "offset": {"rule": "along_normal", "absolute": 0.001}}
json.dump(scene, sys.stdout, indent=1)
PY
    for command in audit render; do
        if [ "$command" = audit ]; then
            args=(audit --scene "$work/scene_$n.json" --variant naive)
        else
            args=(render --scene "$work/scene_$n.json" --variant naive -o "$work/render_$n")
        fi
        read -r seconds rss < <(measure "$rayverify" "${args[@]}")
        printf '%-8s %-11s %12d %10s %14s\n' "$command" "${n}x${n}" $((n * n)) "$seconds" "$rss"
    done
done
