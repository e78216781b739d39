# A long slice runs off the interpreter's lock (other Python threads run), Ctrl-C stops it with
# KeyboardInterrupt, and the progress callback sees the stages on the calling thread.
import subprocess
import sys
import textwrap
import threading

import pytest

import rockslice
from conftest import data

# Table 3's persistent scene at 2.0 m spacing: 125,313 blocks, seconds of work on one thread.
BIG = open(data('table3-persistent.toml')).read().replace('spacing = 3.7', 'spacing = 2.0')

SCRIPT = textwrap.dedent('''
    import os, signal, sys, threading, time
    import rockslice
    ticks = 0
    running = True
    def count():
        global ticks
        while running:
            ticks += 1
            time.sleep(0.001)
    threading.Thread(target=count, daemon=True).start()
    threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
    started = time.time()
    try:
        rockslice.slice(sys.argv[1], threads=1)
        print('finished')
    except KeyboardInterrupt:
        running = False
        print('interrupted %.3f %d' % (time.time() - started, ticks))
    # The module works on after an interruption.
    print('after', len(rockslice.slice(sys.argv[2])))
''')


def test_ctrl_c_interrupts_a_long_slice(tmp_path):
    scene = tmp_path / 'big.toml'
    scene.write_text(BIG)
    r = subprocess.run([sys.executable, '-c', SCRIPT, str(scene), data('cube-3sets.toml')],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split('\n')
    assert lines[0].startswith('interrupted'), r.stdout
    _, seconds, ticks = lines[0].split()
    # Another Python thread ran while the slice did: the lock was free.
    assert int(ticks) > 50
    assert lines[1] == 'after 1000'


def test_progress_callback_sees_every_stage():
    calls = []
    main = threading.get_ident()

    def progress(stage, done, total):
        assert threading.get_ident() == main
        calls.append((stage, done, total))
    scene = data('rock-slope.toml')
    model = rockslice.slice(scene, progress=progress)
    assert calls, 'no progress report'
    stage, done, total = calls[-1]
    assert stage == 'vertices' and done == total == len(model)
    assert all(0 <= d <= t for _, d, t in calls)


def test_an_exception_in_the_callback_stops_the_slice(tmp_path):
    def progress(stage, done, total):
        raise RuntimeError('stop here')
    with pytest.raises(RuntimeError, match='stop here'):
        rockslice.slice(data('rock-slope.toml'), progress=progress)
