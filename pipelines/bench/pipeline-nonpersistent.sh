#!/usr/bin/env bash
# The Fig. 20 (b) end of issue 29: data/table3-lognormal.toml (Table 3's three sets of square
# joints, lognormal sizes, the 0.4 m and 8000 limits) at 3e-2 centres per m3 per set (102,897
# joints, 980,152 blocks), joints -> cut + prune -> vertices -> VTU, each run into an empty
# folder. Per stage: wall seconds, CPU seconds (user + sys) and peak RSS (/usr/bin/time), and
# the cut's own stage times (slice-cut --stats); the 1-minute load average before each run.
# Appends one row per run to results/pipeline-nonpersistent.csv and plots the file:
#   bash pipelines/bench/pipeline-nonpersistent.sh [runs=3] [threads=0 (all cores)] [density=3e-2]
# Wall times move with the neighbours on a shared machine: quote them with the load column,
# and the CPU seconds and peak RSS, which move much less.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tools=${SLICE_BUILD_DIR:-$root/build}/tools
runs=${1:-3}
threads=${2:-0}
density=${3:-3e-2}
results=$root/pipelines/bench/results
csv=$results/pipeline-nonpersistent.csv
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed "s/^density = 1e-3/density = $density/" "$root/data/table3-lognormal.toml" >"$work/scene.toml"
[ "$(grep -cE "^density = $density( |$)" "$work/scene.toml")" = 3 ] || { echo "density not set" >&2; exit 2; }
thread_args=()
[ "$threads" = 0 ] || thread_args=(--threads "$threads")
stages="joints cut_prune vertices export_vtu"
if [ ! -f "$csv" ]; then
  header="run,density,threads,load,blocks,seconds_cut,seconds_finish,seconds_prune"
  for s in $stages; do header="$header,${s}_wall_s,${s}_cpu_s,${s}_rss_mb"; done
  echo "$header,total_wall_s,total_cpu_s,peak_rss_mb" >"$csv"
fi
# stage NAME command...: runs it under /usr/bin/time, appends "wall,cpu,rss" to $row
stage() {
  local name=$1
  shift
  /usr/bin/time -f "%e %U %S %M" -o "$work/time.$name" "$@"
  row="$row,$(awk '{ printf "%.2f,%.2f,%.0f", $1, $2 + $3, $4 / 1024 }' "$work/time.$name")"
}
for run in $(seq 1 "$runs"); do
  rm -rf "$work/out" && mkdir "$work/out" && cd "$work/out" && sync && sleep 1
  load=$(cut -d' ' -f1 /proc/loadavg)
  row=""
  stage joints "$tools/slice-joints" -q "$work/scene.toml" -o joints.h5
  stage cut_prune "$tools/slice-cut" -q joints.h5 --prune -o blocks.h5 --stats stats.json \
    "${thread_args[@]}"
  stage vertices "$tools/slice-vertices" -q blocks.h5 -o geom.h5 "${thread_args[@]}"
  stage export_vtu "$tools/slice-export" -q geom.h5 --format vtu -o blocks.vtu "${thread_args[@]}"
  cut=$(/usr/bin/python3 -c 'import json, sys; s = json.load(open(sys.argv[1]))
print("%d,%.2f,%.2f,%.2f" % (s["blocks"], s["seconds_cut"], s["seconds_finish"], s["seconds_prune"]))' stats.json)
  total=$(/usr/bin/python3 -c 'import sys; v = [float(x) for x in sys.argv[1].split(",")[1:]]
print("%.2f,%.2f,%.0f" % (sum(v[0::3]), sum(v[1::3]), max(v[2::3])))' "$row")
  echo "$run,$density,${threads/#0/all},$load,$cut$row,$total" | tee -a "$csv"
done
/usr/bin/python3 "$root/pipelines/bench/plot_pipeline_nonpersistent.py" "$csv" \
  "$results/pipeline-nonpersistent.png"
