# Runs a rockslice YADE model for a given time and writes how far each body moved to a JSON file:
#   yade -n -x tests/data/yade_motion.py model.py report.json SECONDS
# The model is built by its own script (STEPS = 0 in the export), then run for SECONDS of
# simulated time. `yade -x` exits with 0 even when the script raises, so a failure is written to
# the report ("error") and the test reads it there.
import json
import math
import sys
import time
import traceback

model, report, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
out = {}
try:
    exec(compile(open(model).read(), model, 'exec'))
    start = {b.id: tuple(b.state.pos) for b in O.bodies}
    steps = max(1, int(round(seconds / O.dt)))
    t0 = time.time()
    O.run(steps, True)
    wall = time.time() - t0
    moved, speed = {}, {}
    for b in O.bodies:
        speed[str(b.id)] = b.state.vel.norm() if math.isfinite(b.state.vel.norm()) else None
        p = b.state.pos
        moved[str(b.id)] = [p[k] - start[b.id][k] if math.isfinite(p[k]) else None
                            for k in range(3)]
    out = {'steps': O.iter, 'dt': O.dt, 'time': O.time, 'seconds_per_step': wall / O.iter,
           'law': globals().get('LAW', ''),
           'contacts': len(globals().get('CONTACTS', [])),
           'bonds_left': len(globals().get('bond_of_pair', {})),
           'body_of_block': {str(k): v for k, v in body_of_block.items()},
           'clump_of_cluster': {str(k): v for k, v in clump_of_cluster.items()},
           'moved': moved, 'speed': speed}
except BaseException:
    out = {'error': traceback.format_exc()}
with open(report, 'w') as f:
    json.dump(out, f)
