# Seconds per step of a rockslice YADE model after some settling, engine by engine (run by
# yade-law.sh): yade -n -j1 -x pipelines/bench/yade-law.py model.py WARMUP STEPS OUT.json
# Builds the model (its STEPS must be 0), runs WARMUP steps so that blocks settle into contact,
# then times STEPS steps with YADE's engine timing and writes JSON: bodies, law, cpu seconds a
# step, each engine's seconds a step, real interactions and touching contacts at the end.
import json
import sys
import time

_law = {'model': sys.argv[1], 'warm': int(sys.argv[2]), 'steps': int(sys.argv[3]),
        'out': sys.argv[4]}
exec(compile(open(_law['model']).read(), _law['model'], 'exec'))
O.run(_law['warm'], True)
O.timingEnabled = True
for e in O.engines:
    e.execTime = 0
_law['c0'] = time.process_time()
O.run(_law['steps'], True)
_law['cpu'] = (time.process_time() - _law['c0']) / _law['steps']
json.dump({'bodies': len(O.bodies), 'law': LAW, 'cpu': _law['cpu'],
           'engines': {type(e).__name__: e.execTime / 1e9 / _law['steps'] for e in O.engines},
           'real': O.interactions.countReal(),
           'touching': sum(1 for I in O.interactions
                           if I.geom.penetrationVolume > 0 and I.geom.equivalentPenetrationDepth > 1e-18)},
          open(_law['out'], 'w'))
