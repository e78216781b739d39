# Shared by the pytest tests of the Python module (tests/CMakeLists.txt runs them with Debian's
# /usr/bin/python3, PYTHONPATH=<build>/python and ROCKSLICE_TOOLS=<build>/tools): the real
# tools, the data scenes, and a comparison of HDF5 files with h5py.
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

TOOLS = os.environ.get('ROCKSLICE_TOOLS', '')
SOURCE = os.path.abspath(os.environ.get('ROCKSLICE_SOURCE',
                                         os.path.join(os.path.dirname(__file__), '..', '..')))
DATA = os.path.join(SOURCE, 'data')
# Root attributes that say who made a file: the only ones the module's files may differ in.
PROVENANCE = {'tool', 'tool_version', 'command_line', 'input', 'input_sha256'}


def data(name):
    return os.path.join(DATA, name)


def run_tool(tool, *args, check=True):
    """Runs a built tool; returns the CompletedProcess (text). check: exit 0 required."""
    exe = os.path.join(TOOLS, tool)
    assert os.access(exe, os.X_OK), 'no tool %s (set ROCKSLICE_TOOLS to <build>/tools)' % exe
    r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
    if check:
        assert r.returncode == 0, r.stderr
    return r


def tool_pipeline(tmp, scene, seed=None):
    """slice-joints, slice-cut --prune, slice-vertices on a scene: (joints, blocks, geom)."""
    j, b, g = (os.path.join(tmp, n) for n in ('joints.h5', 'blocks.h5', 'geom.h5'))
    run_tool('slice-joints', scene, '-o', j, '-q', *(['--seed', seed] if seed is not None else []))
    run_tool('slice-cut', j, '--prune', '-o', b, '-q')
    run_tool('slice-vertices', b, '-o', g, '-q')
    return j, b, g


def h5_items(path):
    """Every group, dataset and attribute of an HDF5 file but the provenance attributes:
    {name: (kind, value)}."""
    out = {}
    with h5py.File(path, 'r') as f:
        def attrs(name, obj):
            for k, v in obj.attrs.items():
                if name == '/' and k in PROVENANCE:
                    continue
                out['%s@%s' % (name, k)] = ('attr', np.asarray(v))
        attrs('/', f)

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = ('data', obj[()], obj.dtype.str, obj.shape, obj.chunks,
                             obj.compression)
            else:
                out[name] = ('group',)
            attrs(name, obj)
        f.visititems(visit)
    return out


def assert_same_h5(a, b):
    """The two files hold the same groups, datasets (values, types, shapes, layout) and
    attributes, but for the provenance."""
    x, y = h5_items(a), h5_items(b)
    assert sorted(x) == sorted(y)
    for k in x:
        assert len(x[k]) == len(y[k]), k
        for u, v in zip(x[k], y[k]):
            if isinstance(u, np.ndarray):
                assert u.dtype == v.dtype, k
                assert np.array_equal(u, v, equal_nan=u.dtype.kind == 'f'), k
            else:
                assert u == v, k


def provenance(path):
    with h5py.File(path, 'r') as f:
        return {k: (lambda v: v.decode() if isinstance(v, bytes) else str(v))(f.attrs[k])
                for k in f.attrs if k in PROVENANCE}


def yade_exe():
    """Debian's yade: the YADE tests need it (pipelines/setup installs it); missing, they fail."""
    exe = shutil.which('yade')
    assert exe, 'yade is not installed: pipelines/setup installs it (the YADE tests need it)'
    return exe


@pytest.fixture(scope='session')
def tmp_session(tmp_path_factory):
    return tmp_path_factory.mktemp('rockslice')
