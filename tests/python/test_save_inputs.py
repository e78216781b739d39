# Model.save refuses what the tools refuse for -o (issue 42): a path that is one of the model's
# inputs (the scene, a [[dfn]] file it names) raises rockslice.Error with the tools' wording,
# and an output that is not a regular file (a FIFO, a link to a device) raises OSError; both
# leave the file as it was.
import os

import pytest

import rockslice
from conftest import data

SCENE = '''[scene]
name = "dfn"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
[[dfn]]
file = "discs.csv"
'''
DISCS = 'x,y,z,dip,dip_direction,radius\n5,5,5,60,30,3\n4,6,5,70,200,3\n'


@pytest.fixture
def dfn_scene(tmp_path):
    (tmp_path / 'discs.csv').write_text(DISCS)
    scene = tmp_path / 's.toml'
    scene.write_text(SCENE)
    return scene


def test_save_over_the_scene_or_its_dfn_file_is_refused(tmp_path, dfn_scene):
    discs = tmp_path / 'discs.csv'
    os.symlink(dfn_scene, tmp_path / 'link.toml')
    os.link(discs, tmp_path / 'hard.csv')
    for model in (rockslice.slice(dfn_scene), rockslice.joints(str(dfn_scene))):
        for path, named in ((dfn_scene, 's.toml'), (tmp_path / 'link.toml', 's.toml'),
                            (discs, 'discs.csv'), (tmp_path / 'hard.csv', 'discs.csv'),
                            (tmp_path / '.' / 's.toml', 's.toml')):
            with pytest.raises(rockslice.Error) as e:
                model.save(path)
            assert 'are the same file: the output would overwrite the input' in str(e.value)
            assert named in str(e.value) and str(e.value).startswith(str(path))
            assert e.value.fix == 'give save() a different path; nothing was written'
    # A model made from that model keeps its inputs.
    with pytest.raises(rockslice.Error, match='same file'):
        rockslice.cut(rockslice.joints(dfn_scene)).save(discs)
    assert dfn_scene.read_text() == SCENE and discs.read_text() == DISCS
    assert os.path.islink(tmp_path / 'link.toml')
    assert sorted(os.listdir(tmp_path)) == ['discs.csv', 'hard.csv', 'link.toml', 's.toml']
    rockslice.slice(dfn_scene).save(tmp_path / 'g.h5')  # any other path is written


def test_a_dict_scene_saves_anywhere(tmp_path, monkeypatch):
    # A dict scene stands under the name "scene" in messages and provenance: no file of it.
    monkeypatch.chdir(tmp_path)
    model = rockslice.joints({'scene': {'name': 'd'},
                              'domain': {'box': {'min': [0, 0, 0], 'max': [1, 1, 1]}},
                              'joints': [{'dip': 0, 'dip_direction': 0,
                                          'point': [0.5, 0.5, 0.5]}]})
    model.save('scene')
    assert rockslice.load('scene').joint_count == 1
    model.save('scene')  # again, over the file of that name: not the dict's input


def test_save_to_a_fifo_or_a_link_to_a_device_is_refused(tmp_path):
    model = rockslice.joints(data('cube-3sets.toml'))
    fifo = tmp_path / 'fifo'
    os.mkfifo(fifo)
    with pytest.raises(OSError, match='FIFO'):
        model.save(fifo)
    for device in ('/dev/full', '/dev/null'):
        link = tmp_path / 'dev.h5'
        os.symlink(device, link)
        with pytest.raises(OSError, match='character device'):
            model.save(link)
        assert os.readlink(link) == device
        os.remove(link)
    link = tmp_path / 'out.h5'
    os.symlink('/dev/stdout', link)
    with pytest.raises(OSError, match='/proc/'):
        model.save(link)
    assert os.path.islink(link)
    assert os.path.exists(fifo) and not os.path.isfile(fifo)
    assert sorted(os.listdir(tmp_path)) == ['fifo', 'out.h5']
