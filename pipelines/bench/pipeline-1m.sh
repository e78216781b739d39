#!/usr/bin/env bash
# The million-block pipeline of issue 15: the paper's Table 3 scene with persistent sets at
# 1.0 m spacing (964,156 blocks), joints -> cut + prune -> vertices -> VTU, on all cores, each
# run into an empty folder (replacing the last run's 1.5 GB of outputs would add the kernel's
# freeing of them). Appends one row per run to results/pipeline-1m.csv:
#   bash pipelines/bench/pipeline-1m.sh [runs=10]
# Run it on a quiet machine: the I/O-bound tools move by up to 50 % with the neighbours.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tools=${SLICE_BUILD_DIR:-$root/build}/tools
runs=${1:-10}
csv=$root/pipelines/bench/results/pipeline-1m.csv
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed 's/^spacing = 3.7/spacing = 1.0/' "$root/data/table3-persistent.toml" > "$work/scene.toml"
[ -f "$csv" ] || echo "run,joints_s,cut_prune_s,vertices_s,export_vtu_s,total_s,blocks" > "$csv"
now() { date +%s.%N; }
for run in $(seq 1 "$runs"); do
  rm -rf "$work/out" && mkdir "$work/out" && cd "$work/out" && sync && sleep 1
  t0=$(now)
  "$tools/slice-joints" -q "$work/scene.toml" -o joints.h5; t1=$(now)
  "$tools/slice-cut" -q joints.h5 --prune -o blocks.h5; t2=$(now)
  "$tools/slice-vertices" -q blocks.h5 -o geom.h5; t3=$(now)
  "$tools/slice-export" -q geom.h5 --format vtu -o blocks.vtu; t4=$(now)
  blocks=$("$tools/slice-info" blocks.h5 --json | /usr/bin/python3 -c \
    'import json, sys; print(json.load(sys.stdin)["blocks"]["total"])')
  row=$(/usr/bin/python3 -c 'import sys; t = [float(x) for x in sys.argv[1:6]]; print(",".join(
    "%.2f" % v for v in [t[1]-t[0], t[2]-t[1], t[3]-t[2], t[4]-t[3], t[4]-t[0]]))' \
    "$t0" "$t1" "$t2" "$t3" "$t4")
  echo "$run,$row,$blocks" | tee -a "$csv"
done
