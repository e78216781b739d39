# Runs a rockslice YADE model for a given time and writes, to a JSON file, how far each body has
# moved after every `interval` seconds of simulated time (stability_dem_test.cpp):
#   yade -n -x tests/data/stability-dem/yade_timeline.py model.py report.json SECONDS INTERVAL
# As tests/data/yade_motion.py (whose report this one extends with "times" and "track"): the model
# is built by its own script (STEPS = 0 in the export); `yade -x` exits with 0 even when the
# script raises, so a failure is written to the report ("error") and the test reads it there.
import json
import math
import sys
import time
import traceback

model, report = sys.argv[1], sys.argv[2]
seconds, interval = float(sys.argv[3]), float(sys.argv[4])
out = {}
try:
    exec(compile(open(model).read(), model, 'exec'))
    start = {b.id: tuple(b.state.pos) for b in O.bodies}

    def moved(b):
        p = b.state.pos
        return [p[k] - start[b.id][k] if math.isfinite(p[k]) else None for k in range(3)]

    def distance(b):
        d = moved(b)
        return None if None in d else math.sqrt(sum(x * x for x in d))

    samples = max(1, int(round(seconds / interval)))
    chunk = max(1, int(round(interval / O.dt)))  # steps between two samples
    times, track = [], {str(b.id): [] for b in O.bodies}
    t0 = time.time()
    for _ in range(samples):
        O.run(chunk, True)
        times.append(O.time)
        for b in O.bodies:
            track[str(b.id)].append(distance(b))
    wall = time.time() - t0
    out = {'steps': O.iter, 'dt': O.dt, 'time': O.time, 'seconds_per_step': wall / O.iter,
           'wall_seconds': wall, 'law': globals().get('LAW', ''),
           'contacts': len(globals().get('CONTACTS', [])),
           'bonds_left': len(globals().get('bond_of_pair', {})),
           'body_of_block': {str(k): v for k, v in body_of_block.items()},
           'clump_of_cluster': {str(k): v for k, v in clump_of_cluster.items()},
           'moved': {str(b.id): moved(b) for b in O.bodies},
           'speed': {str(b.id): b.state.vel.norm() if math.isfinite(b.state.vel.norm()) else None
                     for b in O.bodies},
           'times': times, 'track': track}
except BaseException:
    out = {'error': traceback.format_exc()}
with open(report, 'w') as f:
    json.dump(out, f)
