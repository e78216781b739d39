# A scene given as a dict (the tables and keys of a scene file, as tomllib reads them) gives the
# blocks its TOML file gives; a bad key is named by its place in the dict.
import copy
import json
import tomllib

import numpy as np
import pytest

import rockslice
from conftest import data, run_tool
from rockslice import _toml
from test_contract import same_blocks

SCENES = ['cube-3sets.toml', 'rock-slope.toml', 'vajont-section.toml', 'table3-lognormal.toml',
          'tunnel.toml']


def load_dict(name):
    with open(data(name), 'rb') as f:
        return tomllib.load(f)


@pytest.mark.parametrize('scene', SCENES)
def test_dict_scenes_equal_toml_scenes(scene):
    d = load_dict(scene)
    from_file = rockslice.joints(data(scene))
    from_dict = rockslice.joints(d)
    for name in ('joint_normal', 'joint_d', 'joint_centre', 'joint_set', 'joint_kind',
                 'joint_friction_angle'):
        assert np.array_equal(getattr(from_file, name), getattr(from_dict, name)), name
    o1, c1 = from_file.joint_polygons
    o2, c2 = from_dict.joint_polygons
    assert np.array_equal(o1, o2) and np.array_equal(c1, c2)
    if scene in ('table3-lognormal.toml', 'tunnel.toml'):
        return  # joints enough: their blocks take longer (the others cut the same code)
    same_blocks(rockslice.slice(data(scene)), rockslice.slice(d))


def test_dict_values_may_be_numpy_and_tuples():
    d = load_dict('cube-3sets.toml')
    d['domain']['box'] = {'min': np.zeros(3), 'max': (10.0, 10, np.float64(10))}
    d['sets'][0]['spacing'] = np.float32(1.0)
    d['sets'][1]['dip'] = np.int64(90)
    m = rockslice.slice(d)
    assert len(m) == 1000 and np.allclose(m.volume, 1)


def test_dict_seed_and_name():
    d = load_dict('table3-lognormal.toml')
    a = rockslice.joints(d, seed=3)
    d['scene']['seed'] = 3
    b = rockslice.joints(d)
    assert a.seed == b.seed == 3
    assert np.array_equal(a.joint_centre, b.joint_centre)
    assert not np.array_equal(a.joint_centre, rockslice.joints(d, seed=4).joint_centre)
    assert a.name == d['scene']['name']


def test_bad_dict_scenes_name_the_key():
    d = load_dict('cube-3sets.toml')
    bad = copy.deepcopy(d)
    bad['sets'][1]['spaceing'] = bad['sets'][1].pop('spacing')
    with pytest.raises(rockslice.Error) as e:
        rockslice.slice(bad)
    assert e.value.where == "scene['sets'][1]['spaceing']"
    assert str(e.value).startswith("scene['sets'][1]['spaceing']: unknown key 'spaceing'")
    assert 'spacing' in e.value.fix
    bad = copy.deepcopy(d)
    bad['options']['order'] = 'random'
    with pytest.raises(rockslice.Error, match=r"^scene\['options'\]\['order'\]: "):
        rockslice.slice(bad)
    bad = copy.deepcopy(d)
    del bad['domain']
    with pytest.raises(rockslice.Error, match='no \\[domain\\]'):
        rockslice.slice(bad)
    with pytest.raises(TypeError, match='not object'):
        rockslice.slice({'domain': {'box': object()}})


def test_set_dict_has_the_trace_statistics_of_slice_joints(tmp_path):
    # A spaced set and a stochastic set mapped on a vertical wall, one set without a window: the
    # module's set columns trace_* are the statistics slice-info --json lists for slice-joints'
    # file of the same scene.
    window = {'point': [10, 10, 10], 'dip': 90, 'dip_direction': 180, 'width': 16, 'height': 12}
    d = {'scene': {'name': 'mapped', 'seed': 31},
         'domain': {'box': {'min': [0, 0, 0], 'max': [20, 20, 20]}},
         'sets': [{'name': 'bedding', 'dip': 10, 'dip_direction': 140, 'spacing': 2.5,
                   'fisher_kappa': 25, 'mapping': window},
                  {'name': 'J1', 'dip': 80, 'dip_direction': 60, 'spacing': 4},
                  {'name': 'J2', 'dip': 70, 'dip_direction': 300, 'density': 0.01,
                   'size': {'distribution': 'lognormal', 'mean': 6, 'sd': 2},
                   'shape': 'polygon', 'sides': 12, 'mapping': window,
                   'trace_length': {'mean': 4.2, 'sd': 1.9}}]}
    model = rockslice.joints(d)
    sets = model.sets
    model.save(tmp_path / 'j.h5')
    info = json.loads(run_tool('slice-info', tmp_path / 'j.h5', '--json').stdout)
    by_set = info['joints']['by_set']
    assert list(sets['trace_window']) == [True, False, True]
    for s in (0, 2):
        t = by_set[s]['traces']
        assert t['count'] >= 5
        assert sets['trace_count'][s] == t['count']
        assert list(sets['trace_censored'][s]) == t['censored']
        for col, key in (('trace_mean', 'mean'), ('trace_sd', 'sd'),
                         ('trace_complete_mean', 'complete_mean'), ('trace_p21', 'p21')):
            assert sets[col][s] == t[key], col
    assert sets['mapped_mean'][2] == 4.2 and sets['mapped_sd'][2] == 1.9
    assert np.isnan(sets['mapped_mean'][0])
    assert 'traces' not in by_set[1]
    assert sets['trace_count'][1] == 0 and np.isnan(sets['trace_p21'][1])
    # slice-joints on the same scene says the same count.
    toml = tmp_path / 's.toml'
    toml.write_text(_toml.dump(d)[0])
    r = run_tool('slice-joints', toml, '-o', tmp_path / 'j2.h5')
    assert 'set "J2": %d traces on its mapping window' % sets['trace_count'][2] in r.stderr
    # A loaded file gives the same columns.
    loaded = rockslice.load(tmp_path / 'j2.h5').sets
    for col in ('trace_count', 'trace_mean', 'trace_p21'):
        assert np.array_equal(loaded[col], sets[col], equal_nan=True), col
