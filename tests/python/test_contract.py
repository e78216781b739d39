# The minimal contract (issue 27) and the tools' files: rockslice.slice and the stages give the
# blocks the tools give (volumes, flags, clusters, faces, vertices), model.save writes the
# tools' files but for the provenance, rockslice.load reads each of them.

import numpy as np
import pytest

import rockslice
from conftest import assert_same_h5, data, provenance, run_tool, tool_pipeline

# A cube of 1000 unit cubes; a slope with boundary joints, a tunnel's construction joints
# (clusters, removed blocks) and fixed faces; a 2-D section.
SCENES = ['cube-3sets.toml', 'rock-slope.toml', 'vajont-section.toml']


def same_blocks(a, b):
    """Two models hold the same blocks: every array equal, exactly."""
    assert len(a) == len(b)
    for name in ('flags', 'cluster', 'inradius', 'origin', 'bsphere', 'face_offset',
                 'face_normal', 'face_d', 'face_joint', 'volume', 'centroid', 'inertia',
                 'vertex_offset', 'vertices', 'face_vertex_offset', 'face_vertices', 'face_area',
                 'face_joint_fraction'):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype, name
        assert x.shape == y.shape, name
        assert np.array_equal(x, y), name


@pytest.mark.parametrize('scene', SCENES)
def test_slice_equals_the_tools(scene, tmp_path):
    j, b, g = tool_pipeline(tmp_path, data(scene))
    model = rockslice.slice(data(scene))
    assert model.stage == 'geometry'
    tools = rockslice.load(g)
    assert tools.stage == 'geometry'
    # The contract: one volume per block, in the file's order.
    assert isinstance(model.volume, np.ndarray)
    assert model.volume.shape == (len(tools),)
    assert np.array_equal(model.volume, tools.volume)
    same_blocks(model, tools)
    # The files: the same groups, datasets and attributes; only the provenance differs.
    mine = tmp_path / 'mine-geom.h5'
    model.save(mine)
    assert_same_h5(mine, g)
    # With the tool's provenance, the same bytes.
    same = tmp_path / 'same-geom.h5'
    model.save(same, provenance=tools.provenance)
    assert same.read_bytes() == open(g, 'rb').read()
    p = provenance(mine)
    assert p['tool'] == 'rockslice (Python)'
    assert p['input'] == data(scene)
    assert p['input_sha256'] == provenance(j)['input_sha256']  # the scene's hash


def test_the_stages_write_the_tools_files(tmp_path):
    scene = data('rock-slope.toml')
    j, b, g = tool_pipeline(tmp_path, scene, seed=7)
    joints = rockslice.joints(scene, seed=7)
    assert joints.stage == 'joints' and len(joints) == 0 and joints.seed == 7
    joints.save(tmp_path / 'j.h5')
    assert_same_h5(tmp_path / 'j.h5', j)
    joints.save(tmp_path / 'j2.h5', provenance=rockslice.load(j).provenance)
    assert (tmp_path / 'j2.h5').read_bytes() == open(j, 'rb').read()
    cut = rockslice.cut(joints)
    assert cut.stage == 'blocks' and not cut.pruned
    pruned = rockslice.prune(cut)
    assert pruned.stage == 'pruned'
    pruned.save(tmp_path / 'b.h5')
    assert_same_h5(tmp_path / 'b.h5', b)
    pruned.save(tmp_path / 'b2.h5', provenance=rockslice.load(b).provenance)
    assert (tmp_path / 'b2.h5').read_bytes() == open(b, 'rb').read()
    # --compress: the same datasets, deflated as the tools deflate them.
    run_tool('slice-cut', j, '--prune', '--compress', '-o', tmp_path / 'bz.h5', '-q')
    pruned.save(tmp_path / 'bz2.h5', compress=True)
    assert_same_h5(tmp_path / 'bz2.h5', tmp_path / 'bz.h5')
    geom = rockslice.vertices(pruned)
    geom.save(tmp_path / 'g.h5')
    assert_same_h5(tmp_path / 'g.h5', g)
    # The stages left their inputs as they were.
    assert cut.stage == 'blocks' and pruned.stage == 'pruned'
    # slice() with prune=False stops after the cut: slice-cut without --prune.
    run_tool('slice-cut', j, '-o', tmp_path / 'unpruned.h5', '-q')
    unpruned = rockslice.slice(scene, seed=7, prune=False)
    assert unpruned.stage == 'blocks'
    unpruned.save(tmp_path / 'u.h5')
    assert_same_h5(tmp_path / 'u.h5', tmp_path / 'unpruned.h5')


@pytest.mark.parametrize('kind', ['joints', 'blocks', 'geom'])
def test_load_then_save_gives_the_same_bytes(kind, tmp_path):
    files = dict(zip(('joints', 'blocks', 'geom'), tool_pipeline(tmp_path, data('rock-slope.toml'))))
    model = rockslice.load(files[kind])
    assert model.stage == {'joints': 'joints', 'blocks': 'pruned', 'geom': 'geometry'}[kind]
    assert model.provenance['tool'] == {'joints': 'slice-joints', 'blocks': 'slice-cut',
                                        'geom': 'slice-vertices'}[kind]
    out = tmp_path / ('again-%s.h5' % kind)
    model.save(out)
    assert out.read_bytes() == open(files[kind], 'rb').read()


def test_volumes_of_blocks_without_geometry(tmp_path):
    j, b, g = tool_pipeline(tmp_path, data('rock-slope.toml'))
    run_tool('slice-cut', j, '-o', tmp_path / 'unpruned.h5', '-q')
    geom = rockslice.load(g)
    for path in (b, tmp_path / 'unpruned.h5'):
        m = rockslice.load(path)
        assert m.stage in ('pruned', 'blocks')
        assert np.array_equal(m.volume, geom.volume)
        assert np.array_equal(m.centroid, geom.centroid)
        assert np.array_equal(m.inertia, geom.inertia)
    # Vertices follow pruned faces: a model that is not pruned refuses them, saying what to do.
    with pytest.raises(rockslice.Error, match='rockslice.prune'):
        rockslice.load(tmp_path / 'unpruned.h5').vertices
    assert np.array_equal(rockslice.load(b).vertices, geom.vertices)
    # A joints.h5 has no blocks: no volumes, and a line that says so.
    with pytest.raises(rockslice.Error, match='no blocks'):
        rockslice.load(j).volume


def test_arrays_are_views_of_the_model():
    model = rockslice.slice(data('rock-slope.toml'))
    n = len(model)
    assert n > 0
    for name, shape, dtype in (('volume', (n,), np.float64), ('flags', (n,), np.uint8),
                               ('cluster', (n,), np.int64), ('inradius', (n,), np.float64),
                               ('centroid', (n, 3), np.float64), ('inertia', (n, 6), np.float64),
                               ('origin', (n, 3), np.float64), ('vertex_offset', (n + 1,), np.int64),
                               ('face_offset', (n + 1,), np.int64)):
        a = getattr(model, name)
        assert a.shape == shape and a.dtype == dtype, name
        assert not a.flags.writeable, name
        # No copy: two reads share the model's memory.
        assert np.shares_memory(a, getattr(model, name)), name
    # Flat arrays with offsets: block b's vertices, faces and loops.
    off = model.vertex_offset
    assert off[-1] == len(model.vertices)
    assert model.face_offset[-1] == len(model.face_normal) == len(model.face_joint)
    assert model.face_vertex_offset[-1] == len(model.face_vertices)
    assert len(model.face_area) == len(model.face_joint)
    b = int(np.argmax(model.volume))
    faces = range(model.face_offset[b], model.face_offset[b + 1])
    for f in faces:
        loop = model.face_vertices[model.face_vertex_offset[f]:model.face_vertex_offset[f + 1]]
        assert loop.max() < off[b + 1] - off[b]
    # The flags are the tools' bits; fixed is the YADE rule's.
    assert np.array_equal(model.fixed, (model.flags & (rockslice.BOUNDARY | rockslice.FIXED)) != 0)
    assert ((model.flags & rockslice.REMOVED) != 0).sum() > 0  # the slope's excavation
    # An array keeps its model alive.
    v = rockslice.slice(data('cube-3sets.toml')).volume
    assert np.allclose(v, 1.0) and len(v) == 1000


def test_joints_and_sets_as_arrays(tmp_path):
    model = rockslice.joints(data('cube-3sets.toml'))
    assert model.joint_count == 27
    assert model.joint_normal.shape == (27, 3)
    assert np.array_equal(np.unique(model.joint_set), [0, 1, 2])
    # J1 horizontal: z = 1 .. 9.
    j1 = model.joint_set == 0
    assert np.allclose(model.joint_normal[j1], [0, 0, 1])
    assert np.allclose(np.sort(model.joint_d[j1]), np.arange(1, 10))
    assert model.sets['name'] == ['J1', 'J2', 'J3']
    assert np.array_equal(model.sets['joint_count'], [9, 9, 9])
    assert np.array_equal(model.sets['spacing'], [1.0, 1.0, 1.0])
    offset, corners = model.joint_polygons
    assert offset.shape == (28,) and corners.shape == (0, 3)  # persistent joints: no polygons
    assert np.all(model.joint_kind == 0)
    # A stochastic scene's joints have polygons, in global coordinates on their planes.
    st = rockslice.joints(data('table3-lognormal.toml'))
    offset, corners = st.joint_polygons
    assert offset[-1] == len(corners) > 0
    for j in range(min(50, st.joint_count)):
        c = corners[offset[j]:offset[j + 1]]
        assert np.allclose(c @ st.joint_normal[j] - st.joint_d[j], 0, atol=1e-9 * st.length_scale)


def test_threads_give_the_same_blocks():
    scene = data('rock-slope.toml')
    same_blocks(rockslice.slice(scene, threads=1), rockslice.slice(scene, threads=2))


def test_joints_changed_between_stages():
    joints = rockslice.joints(data('cube-3sets.toml'))
    # Without the horizontal set: 100 columns of 10 m.
    columns = rockslice.vertices(rockslice.cut(joints.with_joints(joints.joint_set != 0)))
    assert len(columns) == 100 and np.allclose(columns.volume, 10.0)
    assert joints.joint_count == 27  # the input is as it was
    # Indices, in another order: the same blocks, cut in another order.
    order = np.argsort(-joints.joint_set, kind='stable')
    reordered = joints.with_joints(order)
    assert np.array_equal(reordered.joint_set, joints.joint_set[order])
    blocks = rockslice.vertices(rockslice.cut(reordered))
    assert len(blocks) == 1000 and np.allclose(np.sort(blocks.volume), 1.0)
    with pytest.raises(rockslice.Error, match='joint 27 does not exist'):
        joints.with_joints([0, 27])
    with pytest.raises(rockslice.Error, match="stage 'blocks'"):
        rockslice.cut(joints).with_joints([0])


def test_the_provenance_hashes_every_file_the_scene_names(tmp_path):
    # topo-slope.toml names a surface (topo-slope.asc): slice-joints records and hashes it beside
    # the scene, and so does the module, for a scene file and for a scene given as a dict.
    scene = data('topo-slope.toml')
    j = tmp_path / 'j.h5'
    run_tool('slice-joints', scene, '-o', j, '-q')
    tool = provenance(j)
    assert tool['input'] == scene + '; ' + data('topo-slope.asc')
    assert len(tool['input_sha256'].split('; ')) == 2
    joints = rockslice.joints(scene)
    assert joints.provenance['input'] == tool['input']
    assert joints.provenance['input_sha256'] == tool['input_sha256']
    joints.save(tmp_path / 'mine.h5')
    mine = provenance(tmp_path / 'mine.h5')
    assert mine['input'] == tool['input'] and mine['input_sha256'] == tool['input_sha256']
    # The file's hash changes with the surface's bytes, not only with the scene's.
    asc = tmp_path / 'topo-slope.asc'
    asc.write_bytes(open(data('topo-slope.asc'), 'rb').read() + b'\n')
    toml = tmp_path / 'topo-slope.toml'
    toml.write_bytes(open(scene, 'rb').read())
    other = rockslice.joints(str(toml)).provenance['input_sha256'].split('; ')
    assert other[0] == tool['input_sha256'].split('; ')[0]
    assert other[1] != tool['input_sha256'].split('; ')[1]
