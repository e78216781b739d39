# cmake --install puts the package where Debian's /usr/bin/python3 finds it: installed under
# DESTDIR with the default prefix, the copy imports and slices, and its folder without DESTDIR
# is on that Python's sys.path.
import os
import subprocess

from conftest import data

BUILD = os.environ.get('ROCKSLICE_BUILD', '')


def test_cmake_install_puts_it_on_pythons_path(tmp_path):
    assert os.path.isfile(os.path.join(BUILD, 'CMakeCache.txt')), 'set ROCKSLICE_BUILD'
    env = dict(os.environ, DESTDIR=str(tmp_path))
    r = subprocess.run(['cmake', '--install', BUILD], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    inits = [os.path.join(d, '__init__.py')
             for d, _, files in os.walk(tmp_path) if d.endswith('/rockslice') and
             '__init__.py' in files]
    assert len(inits) == 1, inits
    package = os.path.dirname(os.path.dirname(inits[0]))  # <DESTDIR><prefix>/lib/.../dist-packages
    installed = package[len(str(tmp_path)):]
    path = subprocess.run(['/usr/bin/python3', '-c', 'import sys; print("\\n".join(sys.path))'],
                          capture_output=True, text=True, env={}).stdout.split('\n')
    assert installed in path, (installed, path)
    code = ('import rockslice, rockslice.yade; print(rockslice.__file__); '
            'print(len(rockslice.slice(%r)))' % data('cube-3sets.toml'))
    r = subprocess.run(['/usr/bin/python3', '-c', code], capture_output=True, text=True,
                       env={'PYTHONPATH': package}, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split('\n')[:2] == [inits[0], '1000']
