# Seconds per step of a rockslice YADE model, the model's build left out (run by yade-steps.sh):
#   yade -n -jN -x pipelines/bench/yade-steps.py model.py WARMUP STEPS ROW.csv [PERF.data]
# Builds the model (its STEPS must be 0), runs WARMUP steps, then times STEPS steps with the
# wall clock and the process's CPU clock (all threads) and appends one CSV line to ROW.csv:
#   bodies,pairs,real,build_s,wall_s_per_step,cpu_s_per_step,collider_runs
# With PERF.data, `perf record --call-graph dwarf` samples this process during the timed steps only.
import os
import signal
import subprocess
import sys
import time

# The model runs in this module's globals (it needs YADE's names): ours live in one dict, which
# the model's own names (row, block, ...) cannot overwrite.
_bench = {'model': sys.argv[1], 'warmup': int(sys.argv[2]), 'steps': int(sys.argv[3]),
          'row': sys.argv[4], 'perf': sys.argv[5] if len(sys.argv) > 5 else '', 't0': time.time()}
exec(compile(open(_bench['model']).read(), _bench['model'], 'exec'))
_bench['build'] = time.time() - _bench['t0']
_bench['collider'] = [e for e in O.engines if isinstance(e, InsertionSortCollider)][0]
O.run(_bench['warmup'], True)
_bench['runs0'] = _bench['collider'].numAction
if _bench['perf']:
    _bench['perf'] = subprocess.Popen(['perf', 'record', '-q', '--call-graph', 'dwarf', '-F', '199', '-o',
                                       _bench['perf'], '-p', str(os.getpid())],
                                      stdout=subprocess.DEVNULL)
    time.sleep(2)  # perf attaches to every thread before the timed steps
_bench['w0'], _bench['c0'] = time.time(), time.process_time()
O.run(_bench['steps'], True)
_bench['w1'], _bench['c1'] = time.time(), time.process_time()
if _bench['perf']:
    _bench['perf'].send_signal(signal.SIGINT)
    _bench['perf'].wait()
with open(_bench['row'], 'a') as _f:
    _f.write('%d,%d,%d,%.1f,%.4g,%.4g,%d\n' % (
        len(O.bodies), len(O.interactions), O.interactions.countReal(), _bench['build'],
        (_bench['w1'] - _bench['w0']) / _bench['steps'],
        (_bench['c1'] - _bench['c0']) / _bench['steps'],
        _bench['collider'].numAction - _bench['runs0']))
