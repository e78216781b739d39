# Bad input raises rockslice.Error (a ValueError) carrying the line the tools print after
# "<tool>: error: "; a missing input FileNotFoundError; an output that cannot be written
# OSError. Nothing is written.
import os
import subprocess
import sys

import pytest

import rockslice
from conftest import data, run_tool, tool_pipeline

GOOD = open(data('cube-3sets.toml')).read()

# (what is wrong, scene text)
BAD_SCENES = [
    ('a misspelt key', GOOD.replace('spacing = 1.0', 'spaceing = 1.0', 1)),
    ('a negative spacing', GOOD.replace('spacing = 1.0', 'spacing = -1.0', 1)),
    ('no domain', GOOD.replace('[domain]', '[domian]')),
    ('TOML syntax', GOOD.replace('name = "J1"', 'name = "J1')),
    ('a string for a number', GOOD.replace('dip = 0 ', 'dip = "flat" ', 1)),
    ('an unknown order', GOOD.replace('order = "by-set"', 'order = "random"')),
]


def tool_line(r, tool):
    """The one line a refused tool printed, after "<tool>: error: "."""
    assert r.returncode == 1, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    prefix = tool + ': error: '
    assert lines[0].startswith(prefix)
    return lines[0][len(prefix):]


@pytest.mark.parametrize('what,text', BAD_SCENES, ids=[w for w, _ in BAD_SCENES])
def test_bad_scenes_raise_the_tools_line(what, text, tmp_path):
    scene = tmp_path / 'bad.toml'
    scene.write_text(text)
    line = tool_line(run_tool('slice-joints', scene, '-o', tmp_path / 'j.h5', check=False),
                     'slice-joints')
    for call in (rockslice.slice, rockslice.joints):
        with pytest.raises(rockslice.Error) as e:
            call(str(scene))
        assert isinstance(e.value, ValueError)
        assert str(e.value) == line
        assert e.value.where.startswith(str(scene))
        assert e.value.fix  # every line says how to fix it
    assert os.listdir(tmp_path) == ['bad.toml']


def test_missing_files_raise_file_not_found(tmp_path):
    for call in (rockslice.slice, rockslice.joints, rockslice.load):
        with pytest.raises(FileNotFoundError, match='no-such.toml: no such file'):
            call(str(tmp_path / 'no-such.toml'))


def test_damaged_and_foreign_files_raise_the_tools_line(tmp_path):
    j, b, g = tool_pipeline(tmp_path, data('cube-3sets.toml'))
    damaged = tmp_path / 'damaged.h5'
    damaged.write_bytes(open(g, 'rb').read()[:5000])
    text = tmp_path / 'text.h5'
    text.write_text('not HDF5\n')
    for path in (damaged, text):
        line = tool_line(run_tool('slice-info', path, check=False), 'slice-info')
        with pytest.raises(rockslice.Error) as e:
            rockslice.load(path)
        assert str(e.value) == line


def test_bad_options_raise(tmp_path):
    scene = data('cube-3sets.toml')
    j = tmp_path / 'j.h5'
    run_tool('slice-joints', scene, '-o', j, '-q')
    line = tool_line(run_tool('slice-cut', j, '--lp', 'simplex', '-o', tmp_path / 'b.h5',
                              check=False), 'slice-cut')
    with pytest.raises(rockslice.Error) as e:
        rockslice.slice(scene, lp='simplex')
    assert str(e.value) == line
    with pytest.raises(rockslice.Error, match='threads'):
        rockslice.slice(scene, threads=-1)
    with pytest.raises(rockslice.Error, match='seed: -1 is out of range'):
        rockslice.slice(scene, seed=-1)
    with pytest.raises(rockslice.Error, match='seed: 1.5 is not an integer'):
        rockslice.slice(scene, seed=1.5)
    with pytest.raises(rockslice.Error, match='max_blocks'):
        rockslice.slice(scene, max_blocks=10)
    with pytest.raises(TypeError):
        rockslice.slice(42)
    # The stages refuse what they cannot take.
    joints = rockslice.joints(scene)
    with pytest.raises(rockslice.Error, match='no blocks'):
        rockslice.prune(joints)
    with pytest.raises(rockslice.Error, match='no blocks'):
        rockslice.vertices(joints)


def test_unwritable_outputs_raise_oserror(tmp_path):
    model = rockslice.joints(data('cube-3sets.toml'))
    with pytest.raises(OSError, match='does not exist|No such file'):
        model.save(tmp_path / 'no-dir' / 'j.h5')
    with pytest.raises(OSError):
        model.save(tmp_path)  # a directory
    # A failed save leaves an existing file as it was (and no .partial).
    out = tmp_path / 'j.h5'
    model.save(out)
    before = out.read_bytes()
    (tmp_path / 'j.h5.partial').mkdir()  # where the writer's .partial goes: refused
    with pytest.raises(OSError, match='partial'):
        rockslice.slice(data('rock-slope.toml')).save(out)
    assert out.read_bytes() == before


# Saves under a limit on the size of the files the process writes (RLIMIT_FSIZE: the system
# refuses the write past it, "File too large", as a full disk refuses with "No space left on
# device"), catches the OSError and ends as a script does.
SAVE_UNDER_LIMIT = '''
import resource, signal, sys
import rockslice
model = rockslice.slice(sys.argv[1])
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
hard = resource.getrlimit(resource.RLIMIT_FSIZE)[1]
resource.setrlimit(resource.RLIMIT_FSIZE, (int(sys.argv[3]), hard))
try:
    model.save(sys.argv[2])
    print('saved')
except OSError as e:
    print('refused:', e)
'''


def test_a_refused_save_raises_and_the_script_ends_cleanly(tmp_path):
    # HDF5 1.10 left a file whose last flush failed open, and crashed on it at exit (SIGSEGV):
    # the script had caught the error, yet ended with a segmentation fault.
    scene = data('rock-slope.toml')
    whole = tmp_path / 'whole.h5'
    rockslice.slice(scene).save(whole)
    size = whole.stat().st_size
    out = tmp_path / 'b.h5'
    for limit in [0, 2048] + [size * k // 8 for k in range(1, 8)] + [size - 1, size]:
        r = subprocess.run([sys.executable, '-c', SAVE_UNDER_LIMIT, scene, str(out), str(limit)],
                           capture_output=True, text=True)
        assert r.returncode == 0, 'limit %d: exit %d, %s' % (limit, r.returncode, r.stderr)
        assert not (tmp_path / 'b.h5.partial').exists()
        if limit < size:
            assert r.stdout.startswith('refused: ') and '(File too large)' in r.stdout, r.stdout
            assert not out.exists()
        else:
            assert r.stdout == 'saved\n'
            assert out.read_bytes() == whole.read_bytes()
