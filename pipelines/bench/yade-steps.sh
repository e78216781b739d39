#!/usr/bin/env bash
# YADE speed benchmark (issue 24, docs/yade-speed.md): seconds per step of the exported Polyhedra
# model in Debian's YADE, the model's build left out, on one core (OMP_NUM_THREADS=1 yade -j1)
# and on two (yade -j2). Scenes: data/cube-3sets.toml (1,000 touching unit cubes, none fixed)
# and pipelines/bench/yade-box.toml at three sizes (about 1,000, 10,000 and 50,000 oblique blocks
# of ~1 m3 in a box whose base and sides are fixed). Variants of each model:
#   touching     the model as exported before issue 24: INITIAL_GAP = 0, NOT_AMONG_FIXED = 0
#   export       the model as slice-export writes it now
#   gap-only     INITIAL_GAP as exported, NOT_AMONG_FIXED = 0   (1k box only: what each
#   fixed-pairs  INITIAL_GAP = 0, NOT_AMONG_FIXED as exported    change is worth)
#   volumetric   the model as exported, LAW = 'volumetric' (YADE's own contact law alone, as
#                exported before issue 40): against `export`, the cost of the per-contact law
# Each run builds the model, runs WARMUP steps, then times STEPS steps (fewer for larger
# models, so that a run stays within minutes). Then the 1k box's touching and exported models
# run 150 steps of settling, timed every 10 (yade-settle.py). Writes results/yade-steps.csv,
# results/yade-settle.csv and results/yade-steps.png.
#   bash pipelines/bench/yade-steps.sh                 (after bash pipelines/setup --tests: yade)
#   YADE_STEPS_SIZES="9.6" YADE_STEPS_THREADS="1" bash pipelines/bench/yade-steps.sh   (quick)
#   YADE_STEPS_PERF=dir bash ...    also `perf record -g` the timed steps into dir/*.data
#   YADE_STEPS_VARIANTS="export" YADE_STEPS_SETTLE=0 YADE_STEPS_CSV=results/yade-steps-quiet.csv \
#     bash ...                       only these variants, into another CSV (its own plot beside it)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bench=$root/pipelines/bench
bin=${SLICE_BUILD_DIR:-$root/build}/tools
results=$bench/results
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
read -r -a sizes <<<"${YADE_STEPS_SIZES:-9.6 21.4 37}"
read -r -a threads <<<"${YADE_STEPS_THREADS:-1 2}"
command -v yade >/dev/null || { echo "yade-steps: no yade on PATH; run bash pipelines/setup --tests" >&2; exit 1; }

machine="$(nproc)-vCPU $(lscpu | sed -n 's/^Model name: *//p' | head -n 1)"
csv=${YADE_STEPS_CSV:-$results/yade-steps.csv}
echo "scene,bodies,variant,threads,warmup,steps,pairs,real,build_s,wall_s_per_step,cpu_s_per_step,collider_runs,load_1min,machine" >"$csv"

# model <scene.toml> <dir>: joints, blocks, geometry and the exported script dir/model.py.
model() {
  mkdir -p "$2"
  "$bin/slice-joints" -q "$1" -o "$2/joints.h5"
  "$bin/slice-cut" -q "$2/joints.h5" -o "$2/blocks.h5" --prune
  "$bin/slice-vertices" -q "$2/blocks.h5" -o "$2/geom.h5"
  "$bin/slice-export" -q "$2/geom.h5" --format yade -o "$2/model.py"
  grep -q '^INITIAL_GAP = ' "$2/model.py" && grep -q '^NOT_AMONG_FIXED = ' "$2/model.py" ||
    { echo "yade-steps: $2/model.py has no INITIAL_GAP or NOT_AMONG_FIXED line" >&2; exit 1; }
}

# variant <dir> <name>: dir/<name>.py from dir/model.py.
variant() {
  local gap=1 pairs=1 law=
  case $2 in
    volumetric) law="s/^LAW = .*/LAW = 'volumetric'/" ;;
    touching) gap=0 pairs=0 ;;
    gap-only) pairs=0 ;;
    fixed-pairs) gap=0 ;;
  esac
  sed -e "$([ $gap = 1 ] || echo 's/^INITIAL_GAP = .*/INITIAL_GAP = 0/')" \
      -e "$([ $pairs = 1 ] || echo 's/^NOT_AMONG_FIXED = .*/NOT_AMONG_FIXED = 0/')" \
      -e "${law:-s/^LAW = /LAW = /}" \
      "$1/model.py" >"$1/$2.py"
}

# run <scene name> <dir> <variant> <threads>
run() {
  local n warmup steps perf=()
  n=$(grep -c '^(' "$2/model.py")
  if [ "$n" -lt 2000 ]; then warmup=3 steps=10
  elif [ "$n" -lt 20000 ]; then warmup=2 steps=4
  else warmup=1 steps=2; fi
  if [ -n "${YADE_STEPS_PERF:-}" ]; then
    mkdir -p "$YADE_STEPS_PERF"
    perf=("$YADE_STEPS_PERF/$1-$3-j$4.data")
  fi
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  : >"$work/row"
  OMP_NUM_THREADS=$4 yade -n -j"$4" -x "$bench/yade-steps.py" "$2/$3.py" "$warmup" "$steps" \
    "$work/row" "${perf[@]}" >"$work/yade.log" 2>&1 </dev/null
  [ -s "$work/row" ] || { echo "yade-steps: no timing from $2/$3.py" >&2; tail -n 20 "$work/yade.log" >&2; exit 1; }
  IFS=, read -r bodies pairs real build wall cpu runs <"$work/row"
  echo "$1,$bodies,$3,$4,$warmup,$steps,$pairs,$real,$build,$wall,$cpu,$runs,$load,$machine" | tee -a "$csv"
}

scenes=()
if [ -z "${YADE_STEPS_SIZES:-}" ]; then
  model "$root/data/cube-3sets.toml" "$work/cube-3sets"
  scenes+=(cube-3sets)
fi
for s in "${sizes[@]}"; do
  sed "s/SIZE/$s/g" "$bench/yade-box.toml" >"$work/yade-box-$s.toml"
  model "$work/yade-box-$s.toml" "$work/yade-box-$s"
  scenes+=("yade-box-$s")
done
for scene in "${scenes[@]}"; do
  if [ -n "${YADE_STEPS_VARIANTS:-}" ]; then
    read -r -a variants <<<"$YADE_STEPS_VARIANTS"
  else
    variants=(touching export)
    [ "$scene" != "yade-box-${sizes[0]}" ] || variants+=(gap-only fixed-pairs)
  fi
  for v in "${variants[@]}"; do
    variant "$work/$scene" "$v"
    for t in "${threads[@]}"; do run "$scene" "$work/$scene" "$v" "$t"; done
  done
done

# The 1k box along a settling run, one core: where the time goes once the blocks rest on each
# other (YADE_STEPS_SETTLE=0 skips it).
settle=
if [ "${YADE_STEPS_SETTLE:-150}" -gt 0 ]; then
  settle=$results/yade-settle.csv
  echo "scene,variant,iteration,wall_s_per_step,cpu_s_per_step,pairs,real,machine" >"$settle"
  for v in touching export; do
    : >"$work/settle"
    OMP_NUM_THREADS=1 yade -n -j1 -x "$bench/yade-settle.py" "$work/yade-box-${sizes[0]}/$v.py" \
      "${YADE_STEPS_SETTLE:-150}" 10 "$work/settle" >"$work/yade.log" 2>&1 </dev/null
    sed "s/^/yade-box-${sizes[0]},$v,/; s/\$/,$machine/" "$work/settle" | tee -a "$settle"
  done
fi
/usr/bin/python3 "$bench/yade-plot.py" "$csv" "${csv%.csv}.png" "$settle"
