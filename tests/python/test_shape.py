# The block shape factors per block (model.shape: alpha, beta, beta_k and both classes) against
# slice-info --json's summary of the same geom.h5, on cubes known by hand and a stochastic
# tunnel scene; a section has none (docs/block-shape.md).
import json

import numpy as np
import pytest

import rockslice
from conftest import data, run_tool, tool_pipeline

CLASSES = ['C', 'PC', 'P', 'CE', 'EP', 'E', 'none']  # slice-info's order


def test_unit_cubes_by_hand():
    s = rockslice.slice(data('cube-3sets.toml')).shape
    assert sorted(s) == ['alpha', 'beta', 'beta_k', 'class', 'class_kalenchuk']
    mean = (12 + 12 * np.sqrt(2) + 4 * np.sqrt(3)) / 28  # the 28 chords of a unit cube
    assert len(s['alpha']) == 1000
    assert np.allclose(s['alpha'], 6 * mean / 7.7, rtol=1e-12, atol=0)
    assert np.allclose(s['beta'], 0.25, rtol=0, atol=1e-12)
    assert np.allclose(s['beta_k'], 10 / 9, rtol=1e-9, atol=0)  # T = 4 I: 10 (1/3)^2
    assert (s['class'] == 'C').all() and (s['class_kalenchuk'] == 'C').all()


def summary(classes, volume, keep):
    return [(int((classes[keep] == c).sum()), float(volume[keep][classes[keep] == c].sum()))
            for c in CLASSES]


@pytest.mark.parametrize('stage', ['geometry', 'blocks'])
def test_tunnel_equals_slice_info(stage, tmp_path):
    # tunnel.toml's geom.h5 as the tools make it; the module reads it, or the blocks.h5 before
    # slice-vertices and computes the geometry itself: the same factors either way.
    _, blocks, geom = tool_pipeline(str(tmp_path), data('tunnel.toml'))
    j = json.loads(run_tool('slice-info', geom, '--json').stdout)['shape']
    m = rockslice.load(geom if stage == 'geometry' else blocks)
    s = m.shape
    keep = (m.flags & rockslice.REMOVED) == 0
    assert (~keep).sum() > 0 and keep.sum() == j['blocks']
    vol = rockslice.load(geom).volume
    for key, cls in (('by_class', 'class'), ('by_class_kalenchuk', 'class_kalenchuk')):
        got = summary(s[cls], vol, keep)
        want = [(c['blocks'], c['volume']) for c in j[key]]
        assert [c['class'] for c in j[key]] == CLASSES
        assert [n for n, _ in got] == [n for n, _ in want], key
        assert np.allclose([v for _, v in got], [v for _, v in want], rtol=1e-12, atol=1e-9)
        assert sum(n > 0 for n, _ in got) >= 4, key  # a stochastic rock mass: many shapes
    bk = s['beta_k'][keep]
    assert np.isfinite(bk).sum() == j['beta_kalenchuk']['blocks']
    assert bk.min() == pytest.approx(j['beta_kalenchuk']['min'], rel=1e-12)
    assert bk.max() == pytest.approx(j['beta_kalenchuk']['max'], rel=1e-12)
    assert bk.mean() == pytest.approx(j['beta_kalenchuk']['mean'], rel=1e-12)
    assert (10 / 9 - 1e-9 <= bk).all() and (bk <= 10).all()
    # The classes are those of the factors: UnBlocks-gen's bounds on beta_k (4, 7).
    a, k = s['alpha'], s['beta_k']
    assert (s['class_kalenchuk'][k >= 7] == 'E').all()
    assert (s['class_kalenchuk'][(k < 4) & (a < 2)] == 'C').all()
    assert (s['class_kalenchuk'][(k >= 4) & (k < 7) & (a >= 3)] == 'EP').all()


def test_a_section_has_no_shape():
    m = rockslice.slice(data('vajont-section.toml'))
    with pytest.raises(rockslice.Error, match='3-D blocks'):
        m.shape
