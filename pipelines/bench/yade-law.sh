#!/usr/bin/env bash
# The cost of the YADE export's contact law (issue 40, docs/yade-speed.md "The contact law per
# contact"): the yade-box scene at about 1,000, 10,000 and 50,000 bodies, exported as is
# (--yade-law mohr-coulomb) and with LAW = 'volumetric' (YADE's own law alone), each on one core:
# WARMUP steps of settling, then STEPS timed steps, engine by engine (yade-law.py). Writes
# results/yade-law.csv.
#   bash pipelines/bench/yade-law.sh          (after bash pipelines/setup --tests; about 25 minutes)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bench=$root/pipelines/bench
bin=${SLICE_BUILD_DIR:-$root/build}/tools
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
csv=$bench/results/yade-law.csv
echo "box_edge_m,bodies,law,warmup_steps,timed_steps,real,touching,cpu_s_per_step,interaction_loop_s,contact_law_engine_s,load_1min" >"$csv"
for spec in "9.6 100 50" "21.4 20 5" "37 5 2"; do
  read -r size warm steps <<<"$spec"
  d=$work/$size
  mkdir -p "$d"
  sed "s/SIZE/$size/g" "$bench/yade-box.toml" >"$d/scene.toml"
  "$bin/slice-joints" -q "$d/scene.toml" -o "$d/j.h5"
  "$bin/slice-cut" -q "$d/j.h5" --prune -o "$d/b.h5"
  "$bin/slice-vertices" -q "$d/b.h5" -o "$d/g.h5"
  "$bin/slice-export" -q "$d/g.h5" --format yade -o "$d/mohr-coulomb.py"
  sed "s/^LAW = .*/LAW = 'volumetric'/" "$d/mohr-coulomb.py" >"$d/volumetric.py"
  for law in mohr-coulomb volumetric; do
    load=$(cut -d' ' -f1 /proc/loadavg)
    OMP_NUM_THREADS=1 yade -n -j1 -x "$bench/yade-law.py" "$d/$law.py" "$warm" "$steps" \
      "$d/$law.json" >"$d/$law.log" 2>&1 </dev/null
    [ -s "$d/$law.json" ] || { echo "yade-law: no timing from $d/$law.py" >&2; tail -n 20 "$d/$law.log" >&2; exit 1; }
    /usr/bin/python3 - "$d/$law.json" "$size" "$warm" "$steps" "$load" >>"$csv" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
e = r['engines']
print(','.join(map(str, [sys.argv[2], r['bodies'], r['law'], sys.argv[3], sys.argv[4], r['real'],
                         r['touching'], '%.4g' % r['cpu'], '%.4g' % e['InteractionLoop'],
                         '%.4g' % e.get('PyRunner', 0), sys.argv[5]])))
PY
    tail -n 1 "$csv"
  done
done
