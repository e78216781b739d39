"""A scene given as a dict, written as the TOML text the scene parser reads.

The dict has the tables and keys of a scene file (docs/scenes.md), as tomllib.load gives them:
[scene], [domain], [options] and [rock] are dicts, [[joints]], [[sets]] and [[zones]] lists of
dicts; values are str, int, float, bool, lists and dicts (inline tables), or numpy scalars and
arrays. Tables come out in the dict's order, so entries keep their order within each table.
dump() also says which key each line came from, so that the parser's "<name>:<line>: ..."
messages can name the key instead.
"""
import json
import math
import re

_BARE = re.compile(r'^[A-Za-z0-9_-]+$')


def _key(k):
    if not isinstance(k, str):
        raise TypeError('scene keys are strings, not %r' % (k,))
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v, where):
    if hasattr(v, 'tolist'):  # numpy arrays and scalars
        v = v.tolist()
    if isinstance(v, bool):
        return 'true' if v else 'false'
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return 'nan'
        if math.isinf(v):
            return 'inf' if v > 0 else '-inf'
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, dict):
        return '{ ' + ', '.join('%s = %s' % (_key(k), _value(x, where + '.' + str(k)))
                                for k, x in v.items()) + ' }'
    if isinstance(v, (list, tuple)):
        return '[' + ', '.join(_value(x, '%s[%d]' % (where, i)) for i, x in enumerate(v)) + ']'
    raise TypeError('%s: a scene value is a number, string, bool, list or dict, not %s'
                    % (where, type(v).__name__))


def dump(scene):
    """(text, lines): the TOML text of a scene dict and, per line (from 1), the key it holds,
    as a Python expression on the dict ("scene['sets'][1]['spacing']")."""
    if not isinstance(scene, dict):
        raise TypeError('a scene is a TOML file name or a dict, not %s' % type(scene).__name__)
    out, lines = [], []

    def emit(text, where):
        out.append(text)
        lines.append(where)

    def table(d, where):
        for k, v in d.items():
            emit('%s = %s' % (_key(k), _value(v, '%s[%r]' % (where, k))), '%s[%r]' % (where, k))

    # Keys outside any table first (the parser refuses them, naming them), then the tables.
    tables = []
    for k, v in scene.items():
        if isinstance(v, dict) or (isinstance(v, (list, tuple)) and v and
                                   all(isinstance(x, dict) for x in v)):
            tables.append((k, v))
        else:
            emit('%s = %s' % (_key(k), _value(v, 'scene[%r]' % k)), 'scene[%r]' % k)
    for k, v in tables:
        if isinstance(v, dict):
            emit('[%s]' % _key(k), 'scene[%r]' % k)
            table(v, 'scene[%r]' % k)
        else:
            for i, entry in enumerate(v):
                emit('[[%s]]' % _key(k), 'scene[%r][%d]' % (k, i))
                table(entry, 'scene[%r][%d]' % (k, i))
    return '\n'.join(out) + '\n', lines
