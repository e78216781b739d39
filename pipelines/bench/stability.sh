#!/usr/bin/env bash
# slice-stability against model size (issue 41 item 8): the paper's Table 3 scene with
# persistent sets, spacing 3.7 m (21,108 blocks) down to 1.0 m (964,156 blocks), free on its top
# and two sides (+z,+x,-y: the steep sets daylight there, so blocks fail and successive failure
# runs for many rounds), on 1 and 2 threads. Appends one row per run to
# results/stability.csv; plot with plot_stability.py:
#   bash pipelines/bench/stability.sh [runs=3] [spacings="3.7 2.5 1.8 1.3 1.0"]
# The geom.h5 of each spacing is made once (joints, cut --prune, vertices), untimed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tools=${SLICE_BUILD_DIR:-$root/build}/tools
runs=${1:-3}
spacings=${2:-"3.7 2.5 1.8 1.3 1.0"}
csv=$root/pipelines/bench/results/stability.csv
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ -f "$csv" ] ||
  echo "spacing,threads,run,blocks,contacts,exposed,failing,rounds,contacts_s,bodies_s,analysis_s,tool_s,peak_mb" >"$csv"
for spacing in $spacings; do
  sed "s/^spacing = 3.7/spacing = $spacing/" "$root/data/table3-persistent.toml" >"$work/scene.toml"
  "$tools/slice-joints" -q "$work/scene.toml" -o "$work/joints.h5"
  "$tools/slice-cut" -q "$work/joints.h5" --prune -o "$work/blocks.h5"
  "$tools/slice-vertices" -q "$work/blocks.h5" -o "$work/geom.h5"
  for threads in 1 2; do
    for run in $(seq 1 "$runs"); do
      rm -f "$work/stab.h5"
      /usr/bin/time -f "%e %M" -o "$work/time" "$tools/slice-stability" "$work/geom.h5" \
        -o "$work/stab.h5" --free-faces +z,+x,-y --threads "$threads" 2>"$work/log"
      row=$(/usr/bin/python3 - "$work/log" "$work/time" <<'PY'
import re, sys
log = open(sys.argv[1]).read()
wall, rss = open(sys.argv[2]).read().split()[-2:]
m = re.search(r"(\d+) bodies, (\d+) contacts: (\d+) exposed, (\d+) removable, (\d+) fail .* in (\d+) rounds?", log)
t = re.search(r"time: contacts ([\d.]+) s, bodies ([\d.]+) s, analysis of the exposed bodies ([\d.]+) s", log)
print(",".join([m.group(1), m.group(2), m.group(3), m.group(5), m.group(6), t.group(1), t.group(2),
                t.group(3), wall, "%.0f" % (int(rss) / 1024)]))
PY
)
      echo "$spacing,$threads,$run,$row" | tee -a "$csv"
    done
  done
done
