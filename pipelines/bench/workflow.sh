#!/usr/bin/env bash
# Workflow benchmark (issue 14): docs/workflow.md's realization sweep (pipelines/config.yaml:
# data/table3-lognormal.toml, 8 seeds, VTU, plots, summary) run by Snakemake with --cores 1 and
# --cores 2, each time followed by three reruns with nothing changed; then the same with the
# scene's three densities raised from 1e-3 to 5e-3 and 1e-2 per m3 (about 100,000 and 260,000
# blocks per seed instead of 12,000). Wall times from the shell; results/workflow.csv and results/workflow.png.
#   bash pipelines/bench/workflow.sh        (after bash pipelines/setup --tests: yade, snakemake)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
results=$root/pipelines/bench/results
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }

csv=$results/workflow.csv
echo "scene,density,seeds,cores,blocks_per_seed,full_s,rerun_s" >"$csv"
for density in 1e-3 5e-3 1e-2; do
  scene=$work/table3-lognormal-$density.toml
  sed -E "s/^density = 1e-3( |$)/density = $density\1/" "$root/data/table3-lognormal.toml" >"$scene"
  [ "$(grep -Ec "^density = $density( |$)" "$scene")" -eq 3 ] || { echo "bench: no densities to set" >&2; exit 1; }
  cat >"$work/config.yaml" <<CONF
scenes:
  table3-lognormal: $scene
seeds: 8
out: $work/out
tools: $root/build/tools
exports: [vtu]
plots: true
summary: true
CONF
  for cores in 1 2; do
    rm -rf "$work/out" "$work/.snakemake"
    run() { (cd "$work" && snakemake -s "$root/pipelines/Snakefile" --configfile config.yaml --cores "$cores" -q >"$work/log" 2>&1); }
    t0=$(now); run; t1=$(now)
    full=$(echo "$t1 - $t0" | bc)
    reruns=()
    for _ in 1 2 3; do
      t0=$(now); run; t1=$(now)
      grep -q "Nothing to be done" "$work/log" || { echo "bench: the rerun did something" >&2; cat "$work/log" >&2; exit 1; }
      reruns+=("$(echo "$t1 - $t0" | bc)")
    done
    rerun=$(printf '%s\n' "${reruns[@]}" | sort -n | sed -n 2p)  # the median of three
    blocks=$(awk -F, 'NR > 1 { s += $2; n++ } END { printf "%d", s / n }' \
      "$work/out/table3-lognormal/summary/realizations.csv")
    printf 'table3-lognormal,%s,8,%s,%s,%.2f,%.2f\n' "$density" "$cores" "$blocks" "$full" "$rerun" | tee -a "$csv"
  done
done
/usr/bin/python3 "$root/pipelines/bench/plot_workflow.py" "$csv" "$results/workflow.png"
