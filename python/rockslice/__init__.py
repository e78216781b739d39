"""rockslice in Python: slice rock masses into convex blocks in-process (docs/python.md).

    import rockslice
    model = rockslice.slice('data/rock-slope.toml')      # joints -> cut -> prune -> vertices
    model.volume                                          # numpy, one entry per block
    model.save('geom.h5')                                 # the file slice-vertices writes

rockslice.slice(scene, seed=None, lp='native', threads=0, prune=True) runs the whole chain;
rockslice.load(path) reads a joints.h5, blocks.h5 or geom.h5. The stages one by one:
joints(scene), cut(model), prune(model), vertices(model); stability(model) answers which
blocks fall (slice-stability). A scene is a TOML file's path or a
dict with the same tables and keys. Bad input raises rockslice.Error (a ValueError) with the
line the tools print; a missing file raises FileNotFoundError; a file that cannot be written
OSError. The work runs off the interpreter's lock; Ctrl-C stops it (KeyboardInterrupt).
rockslice.yade builds YADE bodies from a model inside yade.
"""
import os as _os

from ._rockslice import (BOUNDARY, FIXED, REMOVED, Error, Model, __version__, _CutArgs,
                         _cut, _joints, _prune, _save, _slice, _stability, _vertices, _with_joints)
from ._rockslice import load as _load
from . import _toml

__all__ = ['slice', 'load', 'joints', 'cut', 'prune', 'vertices', 'stability', 'Model', 'Error',
           'BOUNDARY', 'REMOVED', 'FIXED', '__version__']

_MAX_SEED = 2 ** 63 - 1
# The name a dict scene stands under in messages before they are rewritten to name its key.
_DICT_NAME = 'scene'


def _error(where, problem, fix):
    """rockslice.Error as the library makes it: "<where>: <problem>; <fix>", and its parts."""
    e = Error(('%s: %s' % (where, problem) + ('; ' + fix if fix else '')).replace('\n', '\\n'))
    e.where, e.problem, e.fix = where, problem, fix
    return e


# Arguments as the library takes them. A value of the wrong type raises TypeError, one that no
# C++ type holds (2**70, 1e400, a lone surrogate, a NUL in a path, an empty path) rockslice.Error
# naming the argument: one line each, never pybind11's four-line TypeError or RuntimeError.
def _path(name, path):
    """A file name (str, bytes or os.PathLike) as a str (os.fsdecode's, which the extension
    encodes back to the same bytes)."""
    if not isinstance(path, (str, bytes, _os.PathLike)):
        raise TypeError('%s is a file name (str, bytes or os.PathLike), not %s'
                        % (name, type(path).__name__))
    path = _os.fspath(path)
    try:
        raw = _os.fsencode(path)
    except UnicodeEncodeError:
        raise _error(name, '%r holds a lone surrogate, which no file name holds' % path,
                     'give the name as bytes, or as os.fsdecode gives it') from None
    if not raw:
        raise _error(name, 'is empty', 'give the name of a file')
    if b'\0' in raw:
        raise _error(name, '%r holds a NUL character, which no file name holds' % path,
                     'remove it')
    return _os.fsdecode(raw)


def _text(name, value):
    """A str the library takes as UTF-8 text."""
    if not isinstance(value, str):
        raise TypeError('%s is a str, not %s' % (name, type(value).__name__))
    try:
        value.encode('utf-8')
    except UnicodeEncodeError:
        raise _error(name, '%r holds a lone surrogate, which is no text' % value,
                     'give valid Unicode text') from None
    return value


def _whole(name, value, bits=63):
    """An integer argument (int() of it, as before) that a C++ integer of `bits` holds."""
    v = int(value)
    if not -2 ** bits <= v < 2 ** bits:
        raise _error(name, '%d is out of range' % v,
                     'give an integer below 2^%d (%d)' % (bits, 2 ** bits))
    return v


def _number(name, value):
    """A float argument: float() of it, rockslice.Error for an int past the doubles."""
    try:
        return float(value)
    except OverflowError:
        raise _error(name, '%d is too large for a double' % value,
                     'give a number of magnitude below 1.8e308') from None


def _seed(seed):
    if seed is None:
        return None
    fix = 'give an integer from 0 to %d (2^63 - 1), as [scene] seed' % _MAX_SEED
    if isinstance(seed, bool) or not hasattr(seed, '__index__'):
        raise _error('seed', '%r is not an integer' % (seed,), fix)
    seed = seed.__index__()
    if not 0 <= seed <= _MAX_SEED:
        raise _error('seed', '%d is out of range' % seed, fix)
    return seed


def _scene(scene):
    """(text, name, lines): a TOML file (text '' and its path) or a dict (its TOML text)."""
    if isinstance(scene, dict):
        text, lines = _toml.dump(scene)
        try:
            text.encode('utf-8')
        except UnicodeEncodeError as e:  # a lone surrogate in a string: no TOML text holds it
            key = lines[text.count('\n', 0, e.start)]
            raise _error(key, 'holds a lone surrogate (%r), which is no text'
                         % text[e.start:e.end], 'give valid Unicode text') from None
        return text, _DICT_NAME, lines
    if isinstance(scene, (str, bytes, _os.PathLike)):
        return '', _path('scene', scene), None
    raise TypeError('a scene is a TOML file name or a dict, not %s' % type(scene).__name__)


def _dict_error(e, lines):
    """The parser's error on a dict scene's TOML text, naming the dict's key for the line."""
    where = getattr(e, 'where', '')
    head, _, line = where.rpartition(':')
    if lines is None or head != _DICT_NAME or not line.isdigit():
        return e
    n = int(line)
    key = lines[n - 1] if 1 <= n <= len(lines) else 'scene'
    return _error(key, e.problem, e.fix)


def _call(name, *args, **kwargs):
    """The call as the provenance's command line records it."""
    parts = [repr(a) if not isinstance(a, dict) else '<dict>' for a in args]
    parts += ['%s=%r' % kv for kv in kwargs.items() if kv[1] is not None]
    return 'rockslice.%s(%s)' % (name, ', '.join(parts))


def _cut_args(lp, threads, max_blocks=0, certify=False):
    a = _CutArgs()
    if not isinstance(lp, str):
        raise _error('lp', '%r is not a backend' % (lp,), 'give "native", "ipopt" or "exact"')
    a.lp, a.threads = _text('lp', lp), _whole('threads', threads, 31)
    a.max_blocks, a.certify = _whole('max_blocks', max_blocks), bool(certify)
    return a


def joints(scene, seed=None, progress=None):
    """The joints of a scene (slice-joints): a Model of stage 'joints'. `seed` replaces the
    scene's [scene] seed, as slice-joints --seed does."""
    text, name, lines = _scene(scene)
    try:
        return _joints(text, name, _seed(seed), _call('joints', scene, seed=seed), progress)
    except Error as e:
        raise _dict_error(e, lines) from None


def slice(scene, seed=None, lp='native', threads=0, prune=True, progress=None,
          max_blocks=0, certify=False):
    """Runs joints -> cut -> prune -> vertices in-process and returns the Model.

    scene: a TOML scene's path or a dict with the same tables and keys; seed: replaces [scene]
    seed; lp: 'native', 'ipopt' or 'exact'; threads: 0 for all cores (the result is the same for
    every count); prune=False stops after the cut (the blocks slice-cut writes without
    --prune; their volumes are computed when asked for). progress(stage, done, total) is
    called on this thread, at most 20 times a second, with the latest report.
    """
    text, name, lines = _scene(scene)
    try:
        return _slice(text, name, _seed(seed), _cut_args(lp, threads, max_blocks, certify),
                      bool(prune), _call('slice', scene, seed=seed, lp=lp, prune=prune),
                      progress)
    except Error as e:
        raise _dict_error(e, lines) from None


def cut(model, lp='native', threads=0, max_blocks=0, certify=False, progress=None):
    """The blocks the joints of `model` make (slice-cut without --prune): a new Model."""
    return _cut(model, _cut_args(lp, threads, max_blocks, certify), _call('cut', lp=lp), progress)


def prune(model, lp='native', threads=0, certify=False, progress=None):
    """The model's blocks without their redundant faces (slice-prune): a new Model."""
    return _prune(model, _cut_args(lp, threads, 0, certify), _call('prune', lp=lp), progress)


def vertices(model, threads=0, lp='native', progress=None):
    """The model with the blocks' vertices, face loops and mass properties (slice-vertices,
    which prunes first if the blocks are not): a new Model."""
    return _vertices(model, _cut_args(lp, threads), _call('vertices'), progress)


def stability(model, free_faces='', density=2650.0, seismic=0.0, seismic_azimuth=0.0,
              water_table=None, support_pressure=0.0, fos_target=1.0, max_group=8, threads=0,
              progress=None):
    """slice-stability in-process: a new Model with model.stability and model.contacts
    (docs/stability.md). free_faces: '+z,-x', the domain faces that are free surfaces; the
    other options as the tool's (density kg/m3, seismic coefficient k towards seismic_azimuth
    degrees from North, water_table z, support_pressure Pa, fos_target, max_group: the most
    bodies in a group that fails together, 1 for one body at a time)."""
    call = _call('stability', free_faces=free_faces or None, density=density, seismic=seismic,
                 seismic_azimuth=seismic_azimuth, water_table=water_table,
                 support_pressure=support_pressure, fos_target=fos_target, max_group=max_group)
    return _stability(model, _text('free_faces', str(free_faces)), _number('density', density),
                      _number('seismic', seismic), _number('seismic_azimuth', seismic_azimuth),
                      None if water_table is None else _number('water_table', water_table),
                      _number('support_pressure', support_pressure),
                      _number('fos_target', fos_target), _whole('max_group', max_group),
                      _whole('threads', threads, 31), call, progress)


def _save_model(self, path, compress=False, provenance=None):
    """Writes the file the tools would write for this model (joints.h5, blocks.h5 or geom.h5):
    the same bytes, but for the provenance attributes (model.provenance; `provenance`, a dict
    with some of its keys, replaces those). compress: as the tools' --compress. Atomic, as
    the tools' outputs: a failure raises OSError and leaves an existing file as it was, as does
    a path that is not a regular file (a FIFO, a device, /dev/stdout). A path that is one of the
    model's inputs (its scene, a file the scene names) raises rockslice.Error, as the tools
    refuse -o on their input."""
    if provenance is not None and not isinstance(provenance, dict):
        raise TypeError('provenance is a dict of str, not %s' % type(provenance).__name__)
    given = dict(provenance or {})
    for key in given:
        if not isinstance(key, str):
            raise TypeError('provenance keys are str, not %s' % type(key).__name__)
    unknown = sorted(set(given) - set(self.provenance))
    if unknown:
        raise _error('provenance', 'unknown keys %s' % ', '.join(unknown),
                     'give some of %s' % ', '.join(sorted(self.provenance)))
    for key, value in given.items():
        _text('provenance[%r]' % key, value)
        if '\0' in value:  # HDF5 strings end at a NUL
            raise _error('provenance[%r]' % key, '%r holds a NUL character' % value,
                         'remove it; nothing was written')
    _save(self, _path('path', path), bool(compress), given)


def _with_joints_model(self, index):
    """A model of stage 'joints' with only the joints `index` names, in that order: a boolean
    mask over the joints or their indices (a permutation changes the order the cut
    introduces them in). For changing the joints between rockslice.joints and rockslice.cut."""
    import numpy as np
    index = np.asarray(index)
    if index.dtype == bool:
        if index.shape != (self.joint_count,):
            raise _error('index', 'a mask of %d values for %d joints' % (index.size,
                                                                          self.joint_count),
                         'give one value per joint')
        index = np.flatnonzero(index)
    elif index.size and index.dtype.kind == 'O' and all(
            hasattr(i, '__index__') and not isinstance(i, bool) for i in index.flat):
        # Python ints past int64 (numpy keeps them as objects): no such joint.
        big = next(int(i) for i in index.flat if not -2 ** 63 <= int(i) < 2 ** 63)
        raise _error('index', 'joint %d does not exist' % big,
                     'give joints from 0 to %d' % (self.joint_count - 1))
    elif index.size and index.dtype.kind not in 'iu':
        raise _error('index', 'is of type %s' % index.dtype, 'give joint indices or a mask')
    elif index.size and index.dtype.kind == 'u' and index.max() >= 2 ** 63:
        raise _error('index', 'joint %d does not exist' % index.max(),
                     'give joints from 0 to %d' % (self.joint_count - 1))
    return _with_joints(self, index.astype(np.int64).ravel().tolist())


def load(path):
    """The model in a joints.h5, blocks.h5 or geom.h5 file (a joints.h5 gives a model of stage
    'joints', without blocks). Raises FileNotFoundError for a missing file and rockslice.Error
    (a ValueError) with the tools' one-line message for a bad one."""
    return _load(_path('path', path))


Model.save = _save_model
Model.with_joints = _with_joints_model
