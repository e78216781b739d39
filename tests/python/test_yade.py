# rockslice.yade.build in Debian's YADE: the bodies, materials, clumps, fixed blocks, time step
# and the first steps of the settling run are those of the script slice-export writes, run by
# YADE from the same program (python/rockslice/yade_program.py, which slice-export embeds).
# YADE must be installed (pipelines/setup): without it these fail, they do not skip.
import json
import os
import subprocess

import numpy as np
import pytest

import rockslice
import rockslice.yade
from conftest import SOURCE, data, run_tool, tool_pipeline, yade_exe

REPORT = os.path.join(SOURCE, 'tests', 'data', 'yade_report.py')

# A model script for yade_report.py: the model built in-process, its names where the exported
# script has them.
INPROC = '''
import rockslice, rockslice.yade
_model = rockslice.load(%r)
_bodies = rockslice.yade.build(_model, steps=%d)
body_of_block = _bodies.body_of_block
clump_of_cluster = _bodies.clump_of_cluster
INITIAL_GAP = _bodies.namespace['INITIAL_GAP']
LAW = _bodies.namespace['LAW']
CONTACTS = _bodies.namespace['CONTACTS']
tan_of_body = _bodies.namespace['tan_of_body']
merged_into = _bodies.namespace['merged_into']
'''


def yade_report(model_script, tmp, name):
    report, log = tmp / (name + '.json'), tmp / (name + '.log')
    with open(log, 'w') as out:
        subprocess.run([yade_exe(), '-n', '-x', REPORT, str(model_script), str(report)],
                       stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                       timeout=900)
    assert report.exists(), open(log).read()[-3000:]
    r = json.load(open(report))
    assert 'error' not in r, r.get('error')
    return r, open(log).read()


@pytest.mark.parametrize('scene,steps', [('rock-slope.toml', 20), ('vajont-section.toml', 5)])
def test_yade_bodies_in_process_equal_the_exported_script(scene, steps, tmp_path):
    j, b, g = tool_pipeline(tmp_path, data(scene))
    exported = tmp_path / 'model.py'
    run_tool('slice-export', g, '--format', 'yade', '--yade-steps', steps, '-o', exported, '-q')
    # One program: the exported script holds the package's program text as it is.
    program = open(os.path.join(os.path.dirname(rockslice.__file__), 'yade_program.py')).read()
    assert program in exported.read_text()

    inproc = tmp_path / 'inproc.py'
    inproc.write_text(INPROC % (str(g), steps))
    a, _ = yade_report(exported, tmp_path, 'exported')
    b_, log = yade_report(inproc, tmp_path, 'inproc')
    assert 'rockslice: building' in log and 'rockslice: done' in log
    assert a['iterations'] == b_['iterations'] == steps
    assert a['dt'] == b_['dt']
    assert a['body_of_block'] == b_['body_of_block']
    assert a['clump_of_cluster'] == b_['clump_of_cluster']
    assert a['initial_gap'] == b_['initial_gap'] == rockslice._rockslice.YADE_INITIAL_GAP
    # The same law and the same contacts, each with its joint's strength.
    assert a['law'] == b_['law'] == 'mohr-coulomb'
    assert a['contacts'] == b_['contacts'] == len(rockslice.load(g)._yade_contacts())
    if scene == 'rock-slope.toml':
        assert a['contacts'] > 0
    assert len(a['bodies']) == len(b_['bodies'])
    model = rockslice.load(g)
    kept = int(((model.flags & rockslice.REMOVED) == 0).sum())
    assert a['merged_into'] == b_['merged_into']
    assert len(a['body_of_block']) + len(a['merged_into']) == kept
    for x, y in zip(a['bodies'], b_['bodies']):
        for k in ('id', 'is_clump', 'clump', 'blocked'):
            assert x.get(k) == y.get(k), (x['id'], k)
        # YADE's own sums (a clump member's mass, a body's volume) may round apart by an ulp.
        for k in ('mass', 'volume', 'friction_deg'):
            assert (k in x) == (k in y), (x['id'], k)
            if k in x:
                assert x[k] == pytest.approx(y[k], rel=1e-13, abs=0), (x['id'], k)
        # After the steps: a one-ulp mass difference grows in the contacts (seen: 5e-11 of the
        # coordinates after 20 steps on rock-slope); a misplaced body would be off by its size.
        assert np.allclose(x['pos'], y['pos'], rtol=0, atol=1e-6 * model.length_scale)
    # The rules, checked on the in-process bodies: fixed blocks held, friction by the rule.
    friction = model.friction_deg()
    fixed = model.fixed
    for block, body in b_['body_of_block'].items():
        row = b_['bodies'][body]
        assert abs(row['friction_deg'] - friction[int(block)]) < 1e-9
        holder = b_['bodies'][row['clump']] if row['clump'] >= 0 else row
        if fixed[int(block)]:
            assert holder['blocked'] == 'xyzXYZ'
        elif model.dimension == 2:
            assert holder['blocked'] == 'yXZ'
    if scene == 'rock-slope.toml':
        assert fixed.any() and b_['clump_of_cluster']  # both rules seen


def test_yade_build_refuses_bad_options_inside_yade(tmp_path):
    script = tmp_path / 'bad.py'
    out = tmp_path / 'out.txt'
    script.write_text('''
import rockslice, rockslice.yade
m = rockslice.slice(%r)
lines = []
for kwargs in ({'density': 0}, {'damping': 1.5}, {'steps': -1}):
    try:
        rockslice.yade.build(m, **kwargs)
        lines.append('built')
    except rockslice.Error as e:
        lines.append(str(e))
try:
    rockslice.yade.build(rockslice.joints(%r))
except rockslice.Error as e:
    lines.append(str(e))
open(%r, 'w').write('\\n'.join(lines))
''' % (data('cube-3sets.toml'), data('cube-3sets.toml'), str(out)))
    subprocess.run([yade_exe(), '-n', '-x', str(script)], stdin=subprocess.DEVNULL,
                   capture_output=True, timeout=600)
    lines = out.read_text().split('\n')
    assert lines[0] == 'density: is 0; give a positive number'
    assert lines[1].startswith('damping: is 1.5')
    assert lines[2].startswith('steps: is -1')
    assert 'no vertices' in lines[3]


def test_yade_build_outside_yade_says_where_it_runs():
    model = rockslice.slice(data('cube-3sets.toml'))
    with pytest.raises(ImportError, match='yade -n -x'):
        rockslice.yade.build(model)
