# DFN files whose set names are no UTF-8 text (issue 42 item 5): rockslice.joints raised
# UnicodeDecodeError, or made a model that Python could not read back. Now the reader refuses
# the name where it reads it: rockslice.Error naming the file and its line, in one line that
# is itself UTF-8 (the byte is quoted as \xe9).
import os
import subprocess

import h5py
import numpy as np
import pytest

import rockslice
from conftest import TOOLS

HEAD = b'''[scene]
name = "text"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
[[dfn]]
'''
FAB = (b'BEGIN FORMAT\nFormat = Ascii\nEND FORMAT\nBEGIN SETS\nSet1 = "J\xe9"\nEND SETS\n'
       b'BEGIN FRACTURE\n1 4 1\n1 1 1 3\n2 8 1 3\n3 8 8 3\n4 1 8 3\n0 0 0 1\nEND FRACTURE\n')
CSV = b'x,y,z,dip,dip_direction,radius,set\n5,5,5,0,0,2,n\xf6rd\n'


@pytest.mark.parametrize('name,text,where', [('net.fab', FAB, 'net.fab:5:'),
                                             ('d.csv', CSV, 'd.csv:2:')])
def test_latin1_set_names_are_refused_where_read(tmp_path, name, text, where):
    (tmp_path / name).write_bytes(text)
    scene = tmp_path / 's.toml'
    scene.write_bytes(HEAD + b'file = "' + name.encode() + b'"\n')
    for make in (rockslice.joints, rockslice.slice):
        with pytest.raises(rockslice.Error) as e:
            make(str(scene))
        message = str(e.value)
        assert where in message and 'not UTF-8' in message and '\\x' in message
        assert '\n' not in message


def test_utf8_set_names_are_read(tmp_path):
    (tmp_path / 'net.fab').write_bytes(FAB.replace(b'J\xe9', 'Jé'.encode()))
    scene = tmp_path / 's.toml'
    scene.write_bytes(HEAD + b'file = "net.fab"\n')
    out = tmp_path / 'j.h5'
    rockslice.joints(str(scene)).save(str(out))
    rockslice.load(str(out))  # read back: the name is UTF-8 text


def test_text_of_a_file_that_is_no_utf8_reads_with_escapes(tmp_path):
    # A scene whose file name is Latin-1 (its [scene] name given, so the tools accept it): the
    # provenance's input path keeps the file name's bytes. Model.provenance raised
    # UnicodeDecodeError; a name and set names written by another program (h5py here) as bytes
    # that are no UTF-8 did too. Now each reads as text, the bad bytes as \xNN escapes.
    scene = os.path.join(os.fsencode(tmp_path), b'sc\xe8ne.toml')
    with open(scene, 'wb') as f:
        f.write(b'[scene]\nname = "text"\n[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n'
                b'[[joints]]\ndip = 0\ndip_direction = 0\npoint = [5, 5, 5]\n')
    out = tmp_path / 'j.h5'
    r = subprocess.run([os.path.join(TOOLS, 'slice-joints'), scene, b'-o', os.fsencode(out), b'-q'],
                       capture_output=True)
    assert r.returncode == 0, r.stderr
    model = rockslice.load(str(out))
    assert model.provenance['input'].endswith('sc\\xe8ne.toml')
    assert 'sc\\xe8ne.toml' in model.provenance['command_line']
    assert len(model.provenance['input_sha256']) == 64
    with h5py.File(out, 'r+') as f:
        f.attrs.modify('name', np.bytes_(b'r\xf6ck'))
    model = rockslice.load(str(out))
    assert model.name == 'r\\xf6ck'
    assert "'r\\xf6ck'" in repr(model)
