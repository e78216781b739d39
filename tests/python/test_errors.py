# Bad input raises rockslice.Error (a ValueError) carrying the line the tools print after
# "<tool>: error: "; a missing input FileNotFoundError; an output that cannot be written
# OSError. Nothing is written.
import os

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
