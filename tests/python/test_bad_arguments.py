# Arguments no C++ type holds (issue 42 item 15): a bad provenance, ints past int64 or the
# doubles, lone surrogates and NUL characters in paths and text, an empty path. Each raises the
# module's documented types (docs/python.md, Errors): rockslice.Error (a ValueError) naming the
# argument for a bad value, TypeError for a wrong type; one line each, never pybind11's
# RuntimeError "Unable to cast" or its four-line TypeError; and nothing is written.
import os

import pytest

import rockslice
from conftest import data

BIG = 2 ** 70


@pytest.fixture(scope='module')
def model():
    return rockslice.joints(data('cube-3sets.toml'))


@pytest.fixture(scope='module')
def geometry():
    return rockslice.slice(data('cube-3sets.toml'))


def one_line(excinfo, *words):
    message = str(excinfo.value)
    assert '\n' not in message, message
    assert 'Unable to cast' not in message and 'incompatible function arguments' not in message
    for w in words:
        assert w in message, message
    return message


def test_bad_provenance(tmp_path, model):
    out = tmp_path / 'j.h5'
    for given, kind, words in (
            ({'tool': 5}, TypeError, ['provenance', 'str', 'int']),
            ([('tool', 'x')], TypeError, ['provenance', 'dict', 'list']),
            ({1: 'x'}, TypeError, ['provenance keys', 'int']),
            ({'tool': '\udc80'}, rockslice.Error, ["provenance['tool']", 'surrogate']),
            ({'tool': 'a\0b'}, rockslice.Error, ["provenance['tool']", 'NUL'])):
        with pytest.raises(kind) as e:
            model.save(out, provenance=given)
        one_line(e, *words)
        assert not os.path.exists(out)
    # The NUL is the caller's mistake, not a disk's: no "disk is not full" advice.
    with pytest.raises(rockslice.Error) as e:
        model.save(out, provenance={'input': 'x\0'})
    assert 'disk' not in str(e.value)


def test_oversized_ints(model, geometry):
    scene = data('cube-3sets.toml')
    for call, name, words in (
            (lambda: rockslice.slice(scene, threads=BIG), 'threads', ['out of range']),
            (lambda: rockslice.slice(scene, max_blocks=BIG), 'max_blocks', ['out of range']),
            (lambda: rockslice.cut(model, threads=2 ** 40), 'threads', ['out of range']),
            (lambda: rockslice.stability(geometry, threads=BIG), 'threads', ['out of range']),
            (lambda: rockslice.stability(geometry, density=10 ** 400), 'density', ['too large']),
            (lambda: model.with_joints([BIG]), 'index', [str(BIG), 'does not exist']),
            (lambda: geometry.friction_deg(10 ** 400), 'default', ['too large']),
            (lambda: rockslice._rockslice._yade_options(steps=BIG), 'steps', ['out of range']),
            (lambda: rockslice._rockslice._yade_options(young=10 ** 400), 'young',
             ['too large'])):
        with pytest.raises(rockslice.Error) as e:
            call()
        assert e.value.where == name
        one_line(e, *words)
    # A wrong type is a TypeError, in one line.
    with pytest.raises(TypeError) as e:
        geometry.friction_deg('thirty')
    one_line(e, 'default', 'str')
    with pytest.raises(TypeError) as e:
        rockslice._rockslice._yade_options(law=3)
    one_line(e, 'law')


def test_lone_surrogates_and_nul_in_paths(tmp_path, model):
    for bad in (str(tmp_path / '\ud800.h5'), str(tmp_path / 'a\0b.h5')):
        what = 'surrogate' if '\ud800' in bad else 'NUL'
        for call in (lambda: model.save(bad), lambda: rockslice.load(bad),
                     lambda: rockslice.joints(bad), lambda: rockslice.slice(bad)):
            with pytest.raises(rockslice.Error) as e:
                call()
            one_line(e, what)
    assert os.listdir(tmp_path) == []
    # A surrogate that stands for a byte (os.fsdecode's) is a file name like any other.
    name = os.fsdecode(b'\xff.h5')
    model.save(tmp_path / name)
    assert os.listdir(tmp_path) == [name]
    assert rockslice.load(tmp_path / name).joint_count == model.joint_count
    # A missing file of such a name: FileNotFoundError, its message not lost to the byte.
    with pytest.raises(FileNotFoundError) as e:
        rockslice.load(tmp_path / os.fsdecode(b'\xfe.h5'))
    one_line(e, 'no such file', '\\xfe')


def test_lone_surrogates_in_text(geometry):
    with pytest.raises(rockslice.Error) as e:
        rockslice.slice(data('cube-3sets.toml'), lp='\udc80')
    one_line(e, 'lp', 'surrogate')
    with pytest.raises(rockslice.Error) as e:
        rockslice.stability(geometry, free_faces='\udc80')
    one_line(e, 'free_faces', 'surrogate')
    with pytest.raises(rockslice.Error) as e:
        rockslice.joints({'scene': {'name': 'a\udc80'}, 'domain': {}})
    one_line(e, "scene['scene']['name']", 'surrogate')
    with pytest.raises(rockslice.Error) as e:
        rockslice._rockslice._yade_options(law='\udc80')
    one_line(e, 'law', 'surrogate')


def test_empty_path_says_so(tmp_path, model):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for call in (lambda: model.save(''), lambda: model.save(b''), lambda: rockslice.load('')):
            with pytest.raises(rockslice.Error) as e:
                call()
            message = one_line(e, 'path: is empty')
            assert 'partial' not in message
        assert os.listdir(tmp_path) == []
    finally:
        os.chdir(cwd)
