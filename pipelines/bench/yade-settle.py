# Seconds per step along a settling run of a rockslice YADE model (run by yade-steps.sh):
#   yade -n -j1 -x pipelines/bench/yade-settle.py model.py STEPS CHUNK OUT.csv
# Builds the model (its STEPS must be 0), then runs STEPS steps in chunks of CHUNK and appends
# one CSV line per chunk: iteration,wall_s_per_step,cpu_s_per_step,pairs,real
# As the blocks come to rest on each other, contacts become real (they overlap): YADE then
# intersects each such pair with CGAL at every step, whatever the export does.
import sys
import time

# The model runs in this module's globals; ours live in one dict that it cannot overwrite.
_settle = {'model': sys.argv[1], 'steps': int(sys.argv[2]), 'chunk': int(sys.argv[3]),
           'out': sys.argv[4]}
exec(compile(open(_settle['model']).read(), _settle['model'], 'exec'))
for _settle['i'] in range(_settle['steps'] // _settle['chunk']):
    _settle['w'], _settle['c'] = time.time(), time.process_time()
    O.run(_settle['chunk'], True)
    with open(_settle['out'], 'a') as _f:
        _f.write('%d,%.4g,%.4g,%d,%d\n' % (
            O.iter, (time.time() - _settle['w']) / _settle['chunk'],
            (time.process_time() - _settle['c']) / _settle['chunk'], len(O.interactions),
            O.interactions.countReal()))
