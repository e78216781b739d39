#!/usr/bin/env bash
# The cut on 1 and 2 threads for non-persistent joints (issue 29): data/table3-lognormal.toml at
# 8e-3 and 3e-2 centres per m3 per set (194,906 and 980,152 blocks), slice-cut (no prune) run
# `runs` times on each thread count, alternating. Records the cut's stage time (--stats
# seconds_cut), the tool's wall and CPU seconds (user + sys), its peak RSS and the 1-minute load
# average before the run, and checks that both thread counts write the same /blocks (h5diff).
# Appends to results/cut-threads.csv and plots it (speed-up = median 1-thread seconds_cut /
# median 2-thread seconds_cut per density):
#   bash pipelines/bench/cut-threads.sh [runs=3] [density ...]
# On a shared machine the speed-up is only meaningful while nothing else runs (load < 0.5).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tools=${SLICE_BUILD_DIR:-$root/build}/tools
runs=${1:-3}
shift || true
densities=("$@")
[ ${#densities[@]} -gt 0 ] || densities=(8e-3 3e-2)
results=$root/pipelines/bench/results
csv=$results/cut-threads.csv
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ -f "$csv" ] ||
  echo "density,blocks,threads,run,load,seconds_cut,seconds_finish,wall_s,cpu_s,peak_rss_mb" >"$csv"
for d in "${densities[@]}"; do
  sed "s/^density = 1e-3/density = $d/" "$root/data/table3-lognormal.toml" >"$work/scene.toml"
  [ "$(grep -cE "^density = $d( |$)" "$work/scene.toml")" = 3 ] || { echo "density not set" >&2; exit 2; }
  "$tools/slice-joints" -q "$work/scene.toml" -o "$work/joints.h5"
  for run in $(seq 1 "$runs"); do
    for t in 1 2; do
      load=$(cut -d' ' -f1 /proc/loadavg)
      /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$tools/slice-cut" -q "$work/joints.h5" \
        -o "$work/blocks-$t.h5" --threads "$t" --stats "$work/stats.json"
      /usr/bin/python3 - "$d" "$t" "$run" "$load" "$work/stats.json" "$work/time" >>"$csv" <<'PY'
import json, sys
d, t, run, load, stats, time = sys.argv[1:]
s = json.load(open(stats))
wall, user, system, rss = open(time).read().split()
print(f"{d},{s['blocks']},{t},{run},{load},{s['seconds_cut']:.3f},{s['seconds_finish']:.3f},"
      f"{float(wall):.2f},{float(user) + float(system):.2f},{int(rss) / 1024:.0f}")
PY
      tail -n 1 "$csv"
    done
    h5diff -q "$work/blocks-1.h5" "$work/blocks-2.h5" /blocks /blocks ||
      { echo "cut-threads: $d: 1 and 2 threads give different blocks" >&2; exit 1; }
  done
done
/usr/bin/python3 "$root/pipelines/bench/plot_cut_threads.py" "$csv" "$results/cut-threads.png"
