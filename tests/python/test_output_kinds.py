# Model.save to every kind of output path (issue 42), as the tools' output_kinds_test.cpp: an
# existing file, a symlink to one (written where it leads, the link kept), a dangling symlink (its
# file made), a FIFO, /dev/null, /dev/full, a symlink into /dev, /dev/stdout, a directory, a path
# in a missing folder and one in a read-only folder. A refusal is an OSError whose message is one
# line naming the path, and nothing on disk changes: types, bytes and link targets compared.
import os
import stat

import pytest

import rockslice
from conftest import data

ROOT = os.geteuid() == 0
OLD = b'old content\n'


@pytest.fixture(scope='module')
def models():
    """A joints model and a geometry model, made once."""
    joints = rockslice.joints(data('cube-3sets.toml'))
    return {'joints': joints, 'geometry': rockslice.vertices(rockslice.cut(joints))}


def snapshot(folder):
    """{path: (mode, bytes or link target)} of everything under folder, and /dev's two."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            p = os.path.join(root, name)
            st = os.lstat(p)
            what = os.readlink(p) if stat.S_ISLNK(st.st_mode) else None
            if stat.S_ISREG(st.st_mode):
                with open(p, 'rb') as f:
                    what = f.read()
            out[os.path.relpath(p, folder)] = (st.st_mode, what)
    for dev in ('/dev/null', '/dev/full'):
        st = os.lstat(dev)
        out[dev] = (st.st_mode, st.st_rdev)
    return out


def no_partial(folder):
    return [f for _, _, files in os.walk(folder) for f in files if f.endswith('.partial')]


def make_file(d):
    (d / 'out.h5').write_bytes(OLD)
    return d / 'out.h5'


def make_link(d):
    (d / 'real.h5').write_bytes(OLD)
    os.symlink('real.h5', d / 'out.h5')
    return d / 'out.h5'


def make_dangling(d):
    os.symlink('new.h5', d / 'out.h5')
    return d / 'out.h5'


def make_dangling_missing(d):
    os.symlink('nowhere/new.h5', d / 'out.h5')
    return d / 'out.h5'


def make_fifo(d):
    os.mkfifo(d / 'out.h5')
    return d / 'out.h5'


def make_dev_link(d):
    os.symlink('/dev/null', d / 'out.h5')
    return d / 'out.h5'


def make_dir(d):
    (d / 'out.h5').mkdir()
    (d / 'out.h5' / 'inside.txt').write_bytes(OLD)
    return d / 'out.h5'


def make_readonly(d):
    (d / 'ro').mkdir()
    os.chmod(d / 'ro', 0o500)
    return d / 'ro' / 'out.h5'


def check_file(d):
    assert (d / 'out.h5').read_bytes()[:8] == b'\x89HDF\r\n\x1a\n'


def check_link(d):
    assert os.readlink(d / 'out.h5') == 'real.h5'
    assert (d / 'real.h5').read_bytes()[:4] == b'\x89HDF'


def check_dangling(d):
    assert os.readlink(d / 'out.h5') == 'new.h5'
    assert (d / 'new.h5').read_bytes()[:4] == b'\x89HDF'


def check_readonly(d):
    assert (d / 'ro' / 'out.h5').read_bytes()[:4] == b'\x89HDF'


# (what, make, check if the save writes; None: it is refused)
KINDS = [
    ('an existing regular file', make_file, check_file),
    ('a symlink to a regular file', make_link, check_link),
    ('a dangling symlink', make_dangling, check_dangling),
    ('a dangling symlink into a missing folder', make_dangling_missing, None),
    ('a FIFO', make_fifo, None),
    ('/dev/null', lambda d: '/dev/null', None),
    ('/dev/full', lambda d: '/dev/full', None),
    ('a symlink into /dev', make_dev_link, None),
    ('/dev/stdout', lambda d: '/dev/stdout', None),
    ('a directory', make_dir, None),
    ('a path in a missing folder', lambda d: d / 'missing' / 'out.h5', None),
    # Root writes into a read-only folder (permissions do not bind it): the file is written.
    ('a path in a read-only folder', make_readonly, check_readonly if ROOT else None),
]


@pytest.mark.parametrize('stage', ['joints', 'geometry'])
@pytest.mark.parametrize('what,make,check', KINDS, ids=[k[0] for k in KINDS])
def test_save_to_every_kind_of_path(tmp_path, models, stage, what, make, check):
    path = make(tmp_path)
    before = snapshot(tmp_path)
    try:
        if check is not None:
            models[stage].save(path)
            check(tmp_path)
        else:
            with pytest.raises(OSError) as e:
                models[stage].save(path)
            message = str(e.value)
            assert '\n' not in message
            assert message.startswith(str(path)), message
            assert snapshot(tmp_path) == before
        assert no_partial(tmp_path) == []
    finally:
        if (tmp_path / 'ro').exists():
            os.chmod(tmp_path / 'ro', 0o700)
