#!/usr/bin/env bash
# Scaling benchmark (docs/benchmarks.md, paper Fig. 20): the paper's Table 3 scene with
# persistent sets, the spacing varied for about 1,000 to 100,000 blocks, cut and pruned with
# and without the spatial index. Writes pipelines/bench/results/scaling.csv and scaling.png.
#   bash pipelines/bench/scaling.sh [spacing ...]     (default spacings below)
#   e.g. a million blocks by hand:  bash pipelines/bench/scaling.sh 1.0
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${SLICE_BUILD_DIR:-$root/build}/tools
results=$root/pipelines/bench/results
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

spacings=("$@")
[ ${#spacings[@]} -gt 0 ] || spacings=(10 7 5.8 4.6 3.7 3.0 2.5 2.15)
csv=$results/scaling.csv
echo "index,spacing,blocks,joints,seconds_cut,seconds_prune,lps_solved,lps_skipped,peak_rss_mb" >"$csv"
for s in "${spacings[@]}"; do
  sed "s/^spacing = 3.7/spacing = $s/" "$root/data/table3-persistent.toml" >"$work/scene.toml"
  "$bin/slice-joints" -q "$work/scene.toml" -o "$work/joints.h5"
  for index in yes no; do
    # Without the index every joint meets every block: quadratic, so only the smaller sizes.
    if [ "$index" = no ] && awk "BEGIN { exit !($s < ${SLICE_NO_INDEX_MIN_SPACING:-2.5}) }"; then
      continue
    fi
    flag=()
    [ "$index" = yes ] || flag=(--no-index)
    /usr/bin/time -f "%M" -o "$work/rss" "$bin/slice-cut" -q "$work/joints.h5" -o "$work/blocks.h5" \
      --prune --threads 1 --stats "$work/stats.json" "${flag[@]}"
    /usr/bin/python3 "$root/pipelines/bench/scaling_row.py" "$work/stats.json" "$work/rss" "$index" "$s" >>"$csv"
    tail -n 1 "$csv"
  done
done
/usr/bin/python3 "$root/pipelines/bench/plot_scaling.py" "$csv" "$results/scaling.png"
