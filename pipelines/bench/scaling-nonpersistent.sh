#!/usr/bin/env bash
# Scaling benchmark for non-persistent joints (the paper's Fig. 20 b): data/table3-lognormal.toml
# (Table 3: three sets of square joints, lognormal sizes of mean 5 m, sd 1 m, the 0.4 m and
# 8000 limits) with the centre density of every set varied for about 1,000 to 1,000,000
# blocks, cut and pruned on one thread with and without the bounding spheres and the grid
# index. Writes pipelines/bench/results/scaling-nonpersistent.csv and .png.
#   bash pipelines/bench/scaling-nonpersistent.sh [density ...]     (default densities below)
# Without the index every joint meets every block (quadratic): only densities up to
# SLICE_NO_INDEX_MAX_DENSITY (default 2e-3, about 30,000 blocks) are run that way.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${SLICE_BUILD_DIR:-$root/build}/tools
results=$root/pipelines/bench/results
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

densities=("$@")
[ ${#densities[@]} -gt 0 ] || densities=(1.5e-4 3e-4 6e-4 1e-3 1.4e-3 2e-3 4e-3 8e-3 1.6e-2 3e-2)
no_index_max=${SLICE_NO_INDEX_MAX_DENSITY:-2e-3}
csv=$results/scaling-nonpersistent.csv
echo "index,density,blocks,joints,seconds_cut,seconds_prune,lps_solved,lps_skipped,peak_rss_mb" >"$csv"
for d in "${densities[@]}"; do
  sed "s/^density = 1e-3/density = $d/" "$root/data/table3-lognormal.toml" >"$work/scene.toml"
  [ "$(grep -cE "^density = $d( |$)" "$work/scene.toml")" = 3 ] || { echo "density not set" >&2; exit 2; }
  "$bin/slice-joints" -q "$work/scene.toml" -o "$work/joints.h5"
  for index in yes no; do
    if [ "$index" = no ] && awk "BEGIN { exit !($d > $no_index_max) }"; then continue; fi
    flag=()
    [ "$index" = yes ] || flag=(--no-index)
    /usr/bin/time -f "%M" -o "$work/rss" "$bin/slice-cut" -q "$work/joints.h5" -o "$work/blocks.h5" \
      --prune --threads 1 --stats "$work/stats.json" "${flag[@]}"
    /usr/bin/python3 "$root/pipelines/bench/scaling_row.py" "$work/stats.json" "$work/rss" "$index" "$d" >>"$csv"
    tail -n 1 "$csv"
  done
done
/usr/bin/python3 "$root/pipelines/bench/plot_scaling.py" "$csv" "$results/scaling-nonpersistent.png" \
  "Table 3 scene, non-persistent joints (lognormal sizes)"
