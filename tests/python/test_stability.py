# rockslice.stability (issue 41): the arrays slice-stability writes, in-process; the file the
# tool writes, byte for byte given its provenance; loaded files carry them; bad options raise.

import os

import h5py
import numpy as np
import pytest

import rockslice
from conftest import SOURCE, data, run_tool, tool_pipeline

STABILITY = ('removable', 'mode', 'fos', 'direction', 'generation', 'planes', 'group')
CONTACTS = ('pairs', 'faces', 'area', 'centroid', 'normal', 'joint', 'fraction', 'free')


def test_stability_equals_the_tool(tmp_path):
    _, _, g = tool_pipeline(tmp_path, data('rock-slope.toml'))
    stab = tmp_path / 'stab.h5'
    run_tool('slice-stability', g, '-o', stab, '--free-faces', '+z,+x', '--seismic', '0.05',
             '--water-table', '20')
    model = rockslice.stability(rockslice.load(g), free_faces='+z,+x', seismic=0.05,
                                water_table=20)
    with h5py.File(stab, 'r') as f:
        for name in STABILITY:
            want = f['stability'][name][()]
            got = model.stability[name]
            assert got.dtype == want.dtype, name
            assert np.array_equal(got, want), name
        for name in CONTACTS:
            assert np.array_equal(model.contacts[name], f['contacts'][name][()]), name
        # Something moves, and something does not: the check is not of empty arrays.
        assert (f['stability']['generation'][()] >= 0).any()
        assert (f['stability']['mode'][()] == 0).any()
    # The tool's file, the same bytes with its provenance; a loaded file has the arrays.
    loaded = rockslice.load(stab)
    same = tmp_path / 'same.h5'
    model.save(same, provenance=loaded.provenance)
    assert same.read_bytes() == stab.read_bytes()
    assert np.array_equal(loaded.stability['fos'], model.stability['fos'])
    # A geom.h5 without it: None.
    assert rockslice.load(g).stability is None and rockslice.load(g).contacts is None


@pytest.mark.parametrize('kwargs, words', [
    ({'density': -1}, '--density'),
    ({'free_faces': '+q'}, '--free-faces'),
    ({'water_table': float('nan')}, '--water-table'),
    ({'fos_target': 0}, '--fos-target'),
    ({'max_group': 0}, '--max-group'),
    ({'max_group': 65}, '--max-group'),
])
def test_bad_options_raise(tmp_path, kwargs, words):
    _, _, g = tool_pipeline(tmp_path, data('cube-3sets.toml'))
    with pytest.raises(rockslice.Error) as e:
        rockslice.stability(rockslice.load(g), **kwargs)
    assert words in str(e.value)


def test_groups_as_the_tool(tmp_path):
    # tests/data/stability-dem/two-block.toml: two blocks that hold alone fail together
    # (docs/stability.md, "Groups"); max_group=1 is the answer one body at a time.
    scene = os.path.join(SOURCE, 'tests', 'data', 'stability-dem', 'two-block.toml')
    _, _, g = tool_pipeline(tmp_path, scene)
    stab = tmp_path / 'stab.h5'
    run_tool('slice-stability', g, '-o', stab, '--free-faces', '+x,+z')
    model = rockslice.stability(rockslice.load(g), free_faces='+x,+z')
    with h5py.File(stab, 'r') as f:
        group = f['stability']['group'][()]
        assert f['stability'].attrs['max_group'] == 8
    moving = np.flatnonzero(model.stability['mode'] > 0)
    assert len(moving) == 2
    assert np.array_equal(model.stability['group'], group)
    assert (group[moving] == moving.min()).all()
    assert (model.stability['generation'][moving] == 0).all()
    alone = rockslice.stability(rockslice.load(g), free_faces='+x,+z', max_group=1)
    assert (alone.stability['group'] == -1).all()
    assert (alone.stability['generation'] == -1).all()


def test_needs_vertices(tmp_path):
    with pytest.raises(rockslice.Error) as e:
        rockslice.stability(rockslice.joints(data('cube-3sets.toml')))
    assert 'vertices' in str(e.value)
