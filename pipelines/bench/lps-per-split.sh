#!/usr/bin/env bash
# Cut LPs per split (issue 29), before and after the geometric shortcuts (cut_reject.hpp):
# data/table3-lognormal.toml as it is, and pipelines/bench/lps-squares.toml and lps-discs.toml
# at three densities of every set. Each scene is cut twice on one thread, by
# slice-cut --no-shortcuts (every pair the index passes goes to the cut LP: "before") and by
# slice-cut (geometry first: "after"), and the two blocks.h5 are compared with h5diff (every
# dataset of /blocks, exactly). Writes pipelines/bench/results/lps-per-split.csv and .png.
#   bash pipelines/bench/lps-per-split.sh [density ...]      (default densities below)
# SLICE_BEFORE_BUILD_DIR: take "before" from another build's slice-cut instead (one without
# the shortcuts, run as it is, e.g. the main checkout's before they were merged).
# The LP counts are deterministic. The times are one run each on whatever else the machine
# runs: the CSV's load column is the 1-minute load average when the scene started.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${SLICE_BUILD_DIR:-$root/build}/tools
results=$root/pipelines/bench/results
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

before_cut=("$bin/slice-cut" --no-shortcuts)
if [ -n "${SLICE_BEFORE_BUILD_DIR:-}" ]; then
  before_cut=("$SLICE_BEFORE_BUILD_DIR/tools/slice-cut")
fi
densities=("$@")
[ ${#densities[@]} -gt 0 ] || densities=(1e-3 4e-3 1.6e-2)

csv=$results/lps-per-split.csv
echo "scene,density,joints,blocks,splits,splits_undone,cut_lps_before,cut_lps_after,rejected_plane,rejected_box,rejected_faces,lps_per_split_before,lps_per_split_after,identical,seconds_cut_before,seconds_cut_after,load,settled_by_limit" >"$csv"

# run NAME DENSITY SCENE.toml
run() {
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  "$bin/slice-joints" -q "$3" -o "$work/joints.h5"
  "${before_cut[@]}" -q "$work/joints.h5" -o "$work/before.h5" --threads 1 --stats "$work/before.json"
  "$bin/slice-cut" -q "$work/joints.h5" -o "$work/after.h5" --threads 1 --stats "$work/after.json"
  local identical=yes
  h5diff -q "$work/before.h5" "$work/after.h5" /blocks /blocks || identical=no
  /usr/bin/python3 - "$1" "$2" "$work/before.json" "$work/after.json" "$identical" "$load" >>"$csv" <<'PY'
import json, sys
name, density, before, after, identical, load = sys.argv[1:]
b, a = json.load(open(before)), json.load(open(after))
for k in ("blocks", "splits"):
    assert a[k] == b[k], f"{name}: {k} differs: {b[k]} before, {a[k]} after"
# A pair the size limit settles before the LP is a split undone before if the plane cut.
assert a["splits_undone"] <= b["splits_undone"] <= a["splits_undone"] + a["pairs_settled_by_limit"], name
splits = a["splits"]
print(f"{name},{density},{a['joints']},{a['blocks']},{splits},{a['splits_undone']},"
      f"{b['lps_cut_test']},{a['lps_cut_test']},{a['pairs_rejected_plane']},"
      f"{a['pairs_rejected_box']},{a['pairs_rejected_faces']},"
      f"{b['lps_cut_test'] / splits:.3f},{a['lps_cut_test'] / splits:.3f},{identical},"
      f"{b['seconds_cut']:.3f},{a['seconds_cut']:.3f},{load},{a['pairs_settled_by_limit']}")
PY
  tail -n 1 "$csv"
  [ "$identical" = yes ] || { echo "lps-per-split: $1 at $2: blocks differ (h5diff)" >&2; exit 1; }
}

run table3-lognormal 1e-3 "$root/data/table3-lognormal.toml"
for shape in squares discs; do
  for d in "${densities[@]}"; do
    sed "s/^density = 1e-3/density = $d/" "$root/pipelines/bench/lps-$shape.toml" >"$work/scene.toml"
    [ "$(grep -cE "^density = $d( |$)" "$work/scene.toml")" = 3 ] || { echo "density not set" >&2; exit 2; }
    run "$shape" "$d" "$work/scene.toml"
  done
done
/usr/bin/python3 "$root/pipelines/bench/plot_lps_per_split.py" "$csv" "$results/lps-per-split.png"
