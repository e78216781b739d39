# Renders blocks.vtu (slice-export --format vtu) to a PNG with ParaView, removed blocks absent
# (they are not in the file), joints optional:
#   pvpython pipelines/render.py [--view V] [--color-by NAME] [--range R] [--scale S]
#                                blocks.vtu picture.png [joints.vtu]
# Colours (--color-by NAME, also --colour-by: any cell array of the VTU; a vector array by its
# length). Default: fos in a VTU of slice-stability's output, else volume.
#   fos: a diverging map, red below 1 (the blocks that fail), pale yellow at 1, blue above,
#     0..2 unless --range says otherwise; blocks that cannot move (fos NaN, or +inf) grey.
#   an integer array (block_id, cluster, mode, generation, ...): its whole range, min..max.
#   any other (volume, inradius, aspect_ratio, ...): the 2nd to the 98th percentile of its
#     finite values, so a few tiny or huge blocks do not squash the scale; values outside take
#     the end colours.
# --range pLO,pHI: percentiles (0..100) of the array's finite values; --range LO,HI: values.
# --scale log|linear (default: log for a positive range wider than a factor of 10, but fos).
# Camera, --view:
#   AZ,EL       from azimuth AZ (degrees clockwise from North, +y: 90 looks from the East
#               towards the West) and elevation EL (degrees above the horizontal, -90..90);
#   NAME[,EL]   north, north-east, east, south-east, south, south-west, west, north-west (or
#               n, ne, e, se, s, sw, w, nw), elevation 30 unless given; top, bottom (straight
#               down with North up, straight up);
#   free        from outside the free faces: along the area-weighted mean outward normal of the
#               faces no other block covers (free_faces() says which count), turned 30
#               degrees towards the South, its elevation held to 20..45 degrees (-45..-20 for
#               faces that face down more than 20), so the faces are seen at an angle with
#               the model's side; steeper than 80 degrees, from the South-East (141.5). Where
#               nothing tells (no such face, or they face every way, as round a tunnel), the
#               default view, and the line says why.
#   default     a stability VTU: free; any other: from the South-East and above, as always.
# A view other than the default South-East is taken from the distance that fits the model's
# bounding box in. A 2-D section is always seen square on, from -y (--view does not apply).
# It needs an X server (Debian's ParaView renders through GLX only): pipelines/render starts its
# own Xvfb, finds a pvpython and turns failures into one line. Bad input: one line on stderr
# starting "render.py: error:", exit 1. Done: one line on stdout saying what it coloured by (the
# range, at 9 digits), where it looked from and the direction it looked in.
import math
import os
import sys

# An unpacked python3-paraview (pipelines/render) comes second on pvpython's path, after the
# system's dist-packages where python3-vtk9 keeps an incompatible vtkmodules: put the
# directories of PYTHONPATH first again.
first = [p for p in os.environ.get('PYTHONPATH', '').split(':') if p]
sys.path = first + [p for p in sys.path if p not in first]

import numpy as np  # noqa: E402
from paraview import servermanager  # noqa: E402
from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,  # noqa: E402
                             GetScalarBar, PythonCalculator, Render, SaveScreenshot,
                             Show, XMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

USAGE = ('usage: pvpython render.py [--view AZ,EL|NAME[,EL]|free] [--color-by NAME] '
         '[--range pLO,pHI|LO,HI] [--scale log|linear] blocks.vtu picture.png [joints.vtu]')
# Today's camera, from the South-East and above: the offset from the focal point in units of the
# model's size (azimuth 141.5 degrees, elevation 26.9 degrees).
SOUTH_EAST = (1.35, -1.7, 1.1)
NAMED = {'north': 0, 'north-east': 45, 'east': 90, 'south-east': 135, 'south': 180,
         'south-west': 225, 'west': 270, 'north-west': 315}
SHORT = {'n': 'north', 'ne': 'north-east', 'e': 'east', 'se': 'south-east', 's': 'south',
         'sw': 'south-west', 'w': 'west', 'nw': 'north-west'}
NAMED_ELEVATION = 30.0
# --view free: the elevation of the mean normal is held to this band (degrees, or its negative),
# and its azimuth turned this far towards the South: a face seen square on looks flat, from the
# horizontal it shows no depth, from straight above no sides; at an angle it shows the model's
# side too (the profile of a cut or slope).
FREE_ELEVATION = (20.0, 45.0)
FREE_TURN = 30.0
# Of the free faces' area: a shorter mean normal has no direction (faces all round a tunnel).
MIN_MEAN_NORMAL = 0.1
# A mean normal steeper than this (degrees) has no azimuth worth taking: the South-East's.
STEEP = 80.0
DEFAULT_PERCENTILES = (2.0, 98.0)
# factor of safety -> colour: ColorBrewer's RdYlBu, red at 0, pale yellow at 1, blue at 2.
FOS_RANGE = (0.0, 2.0)
FOS_POINTS = [0.0, 0.647, 0.0, 0.149,
              0.5, 0.957, 0.427, 0.263,
              1.0, 1.0, 1.0, 0.749,
              1.5, 0.455, 0.678, 0.820,
              2.0, 0.192, 0.212, 0.584]
CANNOT_MOVE = [0.82, 0.82, 0.82]  # NaN: a neutral light grey
TITLES = {'volume': 'block volume [m3]', 'fos': 'factor of safety', 'inradius': 'inradius [m]',
          'aspect_ratio': 'aspect ratio', 'mode': 'failure mode', 'generation': 'failure round',
          'block_id': 'block id'}


def bad(what):
    print('render.py: error: ' + what, file=sys.stderr)
    sys.exit(1)


def number(text):
    """A finite float, or None."""
    try:
        v = float(text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def parse_view(text):
    """--view's value -> ('angles', az, el, label) | ('free',) | ('default',)."""
    how = ('--view %s: give AZ,EL in degrees (azimuth clockwise from North, elevation -90..90, '
           'e.g. 270,30 to look from the West), a direction (north, north-east, ..., west, '
           'north-west or n, ne, ..., nw; optionally ,EL), top, bottom, free or default' % text)
    t = text.strip().lower()
    if t in ('free', 'default'):
        return (t,)
    if t in ('top', 'bottom'):
        return ('angles', 180.0, 90.0 if t == 'top' else -90.0, t)
    parts = t.split(',')
    name = SHORT.get(parts[0], parts[0])
    if len(parts) > 2 or len(parts) == 1 and name not in NAMED:
        bad(how)
    if name in NAMED:
        az, label = float(NAMED[name]), name if len(parts) == 1 else t
    else:
        az, label = number(parts[0]), None
    el = number(parts[1]) if len(parts) == 2 else NAMED_ELEVATION
    if az is None or el is None or not -90 <= el <= 90:
        bad(how)
    return ('angles', az % 360.0, el, label)


def parse_range(text):
    """--range's value -> ('p', lo, hi) percentiles or ('v', lo, hi) values."""
    how = ('--range %s: give two percentiles pLO,pHI (0 <= LO < HI <= 100, e.g. p2,p98) or two '
           'values LO,HI (LO < HI, e.g. 0,1.5)' % text)
    parts = text.strip().lower().split(',')
    if len(parts) != 2:
        bad(how)
    pct = [p.startswith('p') for p in parts]
    if pct[0] != pct[1]:
        bad(how + '; not one of each')
    lo, hi = (number(p[1:] if pct[0] else p) for p in parts)
    if lo is None or hi is None or not lo < hi or pct[0] and not 0 <= lo < hi <= 100:
        bad(how)
    return ('p' if pct[0] else 'v', lo, hi)


args, view_spec, colour_by, range_spec, scale = [], ('default',), None, None, None
argv = sys.argv[1:]
while argv:
    a = argv.pop(0)
    name, eq, value = a.partition('=')
    if name in ('--view', '--color-by', '--colour-by', '--range', '--scale'):
        if not eq:
            if not argv:
                bad('%s needs a value; %s' % (a, USAGE))
            value = argv.pop(0)
        if name == '--view':
            view_spec = parse_view(value)
        elif name == '--range':
            range_spec = parse_range(value)
        elif name == '--scale':
            if value not in ('log', 'linear'):
                bad('--scale %s: give log or linear (default: log for a positive range wider '
                    'than a factor of 10)' % value)
            scale = value
        else:
            if not value:
                bad('%s: give the name of a cell array of the VTU' % name)
            colour_by = value
    elif a.startswith('-') and len(a) > 1:
        bad('unknown option %s; %s' % (a, USAGE))
    else:
        args.append(a)
if len(args) not in (2, 3):
    bad(USAGE)
blocks_file, picture = args[0], args[1]
for f in args[:1] + args[2:]:
    if not os.path.isfile(f):
        bad('%s: no such file; give a .vtu from slice-export --format vtu' % f)

view = GetActiveViewOrCreate('RenderView')
view.ViewSize = [1000, 620]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 1
try:  # ParaView 5.10+: a plain background instead of the palette's gradient
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

blocks = XMLUnstructuredGridReader(FileName=[blocks_file])
blocks.UpdatePipeline()
if blocks.GetDataInformation().GetNumberOfCells() == 0:
    bad('%s: no blocks read (not a VTU unstructured grid, or empty); give blocks.vtu from '
        'slice-export --format vtu' % blocks_file)
# The cells, here in pvpython (a few ms for 10^4 blocks): the range, the camera and the line.
grid = servermanager.Fetch(blocks)
cells = grid.GetCellData()
present = [cells.GetArrayName(i) for i in range(cells.GetNumberOfArrays())]
stability = 'fos' in present
if stability and 'mode' not in present:
    bad('%s: a cell array "fos" but no "mode"; give the VTU slice-export --format vtu writes '
        'from slice-stability\'s output' % blocks_file)
if colour_by is None:
    colour_by = 'fos' if stability else 'volume'
if colour_by not in present:
    bad('%s: no cell array "%s"; the cell arrays are %s: give one of them to --color-by'
        % (blocks_file, colour_by, ', '.join(present) if present else 'none'))
array = cells.GetArray(colour_by)
values = vtk_to_numpy(array).astype(float)
if values.ndim == 2:  # a vector (direction): its length, as ParaView's 'Magnitude'
    values = np.sqrt((values * values).sum(axis=1))
finite = values[np.isfinite(values)]
integer = array.GetDataType() not in (10, 11)  # VTK_FLOAT, VTK_DOUBLE
is_fos = colour_by == 'fos'

# The range.
if range_spec is not None and range_spec[0] == 'v':
    lo, hi = range_spec[1], range_spec[2]
    how = 'values given'
elif finite.size == 0:
    lo, hi = FOS_RANGE if is_fos else (0.0, 1.0)
    how = 'no finite value'
elif range_spec is not None or not (is_fos or integer):
    p = range_spec[1:] if range_spec is not None else DEFAULT_PERCENTILES
    lo, hi = (float(v) for v in np.percentile(finite, p))
    how = 'p%g,p%g of %d finite values' % (p[0], p[1], finite.size)
elif is_fos:
    lo, hi = FOS_RANGE
    how = 'fixed: 1 in the middle'
else:
    lo, hi = float(finite.min()), float(finite.max())
    how = 'min,max of %d values' % finite.size
if not hi > lo:  # one value: a range around it, or ParaView picks its own
    hi = lo + (abs(lo) if lo else 1.0)
    how += '; all %.9g, widened' % lo
if scale is None:
    scale = 'log' if not is_fos and lo > 0 and hi > 10 * lo else 'linear'
elif scale == 'log' and lo <= 0:
    bad('--scale log: the range of %s starts at %.9g; a log scale needs it positive: give '
        '--range with LO > 0 or --scale linear' % (colour_by, lo))

source = blocks
if np.isinf(values).any():  # +inf (fos: nothing can move) would take the end colour: NaN's
    source = PythonCalculator(Input=blocks, ArrayAssociation='Cell Data',
                              ArrayName=colour_by,
                              Expression='numpy.where(numpy.isinf(%s), numpy.nan, %s)'
                              % (colour_by, colour_by))
shown = Show(source, view)
shown.Representation = 'Surface With Edges'
shown.EdgeColor = [0.15, 0.15, 0.15]
bounds = grid.GetBounds()
centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
section = bounds[2] == bounds[3]  # a 2-D section in (x, z) (docs/2d.md)

ColorBy(shown, ('CELLS', colour_by))
lut = GetColorTransferFunction(colour_by)
lut.AutomaticRescaleRangeMode = 'Never'  # the range chosen here, whatever the data
if array.GetNumberOfComponents() > 1:
    lut.VectorMode = 'Magnitude'
if is_fos:
    lut.ColorSpace = 'Lab'
    lut.RGBPoints = FOS_POINTS
    lut.NanColor = CANNOT_MOVE
else:
    lut.ApplyPreset('Viridis (matplotlib)', True)
lut.RescaleTransferFunction(lo, hi)
if scale == 'log':
    lut.MapControlPointsToLogSpace()
    lut.UseLogScale = 1
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view)
bar.Title = TITLES.get(colour_by, colour_by)
if section and colour_by == 'volume':
    bar.Title = 'block area [m2]'
bar.ComponentTitle = '(length)' if array.GetNumberOfComponents() > 1 else ''
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = bar.LabelFontSize = 14
bar.AddRangeLabels = 1
bar.RangeLabelFormat = '%-.3g'
if is_fos:
    bar.DrawNanAnnotation = 1
    bar.NanAnnotation = 'cannot move'
    movable = np.isfinite(values)
    what = ('%d of %d blocks can move, %d below 1, the rest grey'
            % (int(movable.sum()), len(values), int((values[movable] < 1).sum())))
else:
    what = '%d blocks' % len(values)
colouring = '%s from %.9g to %.9g (%s, %s scale): %s' % (colour_by, lo, hi, how, scale, what)

if len(args) == 3:
    joints = XMLUnstructuredGridReader(FileName=[args[2]])
    j = Show(joints, view)
    j.DiffuseColor = j.AmbientColor = [0.8, 0.2, 0.1]
    j.Opacity = 0.25


def offset(azimuth, elevation):
    """The unit vector from the focal point towards a camera at azimuth (clockwise from North,
    +y) and elevation (degrees)."""
    a, e = math.radians(azimuth), math.radians(elevation)
    return [math.sin(a) * math.cos(e), math.cos(a) * math.cos(e), math.sin(e)]


def fitted(step, up):
    """The camera offset along step (a unit vector from the focal point towards the camera;
    up: the view up, not parallel to it) at the distance where the model's bounding box fills
    the picture: every corner within the 30-degree view angle, with a margin, the width a
    little narrower for the scalar bar."""
    back = step
    right = [up[1] * back[2] - up[2] * back[1], up[2] * back[0] - up[0] * back[2],
             up[0] * back[1] - up[1] * back[0]]
    rn = math.sqrt(sum(c * c for c in right))
    right = [c / rn for c in right]
    up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
          back[0] * right[1] - back[1] * right[0]]
    t = math.tan(math.radians(15.0))
    need = 0.0
    for i in range(8):
        corner = [bounds[2 * k + ((i >> k) & 1)] - centre[k] for k in range(3)]
        z = sum(a * b for a, b in zip(corner, back))
        u = abs(sum(a * b for a, b in zip(corner, up)))
        r = abs(sum(a * b for a, b in zip(corner, right)))
        need = max(need, z + 1.1 * u / t, z + 1.1 * r / (t * 1.3))
    return [c * need for c in back]


def faces_of(g):
    """Every face of every polyhedral cell: cell (F), area (F), unit outward normal (F, 3),
    centre (F, 3: the mean of its corners, inside it: the faces are convex); the cells'
    half-spaces as (N, M, 4) rows (normal, d) padded with rows that hold everywhere
    (0, 0, 0, 1); the cells' bounding boxes (N, 3) twice. slice-export writes each block as one VTK
    polyhedron (type 42) with its own points."""
    stream = vtk_to_numpy(g.GetFaces())
    where = vtk_to_numpy(g.GetFaceLocations())
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    cell, area, normal, middle, counts = [], [], [], [], []
    lo_box = np.full((len(where), 3), np.inf)
    hi_box = np.full((len(where), 3), -np.inf)
    for c, at in enumerate(where):
        if at < 0:
            counts.append(0)
            continue
        n, k = int(stream[at]), int(at) + 1
        ids_all = []
        for _ in range(n):
            m = int(stream[k])
            ids_all.append(stream[k + 1:k + 1 + m])
            k += 1 + m
        corners = pts[np.concatenate(ids_all)]
        centre_c = corners.mean(axis=0)
        lo_box[c], hi_box[c] = corners.min(axis=0), corners.max(axis=0)
        for ids in ids_all:
            p = pts[ids]
            vec = 0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)  # Newell: area vector
            a = float(np.linalg.norm(vec))
            if a == 0:
                continue
            mid = p.mean(axis=0)
            u = vec / a
            if np.dot(u, mid - centre_c) < 0:
                u = -u
            cell.append(c)
            area.append(a)
            normal.append(u)
            middle.append(mid)
        counts.append(n)
    cell, area = np.array(cell, dtype=int), np.array(area)
    normal, middle = np.array(normal).reshape(-1, 3), np.array(middle).reshape(-1, 3)
    planes = np.zeros((g.GetNumberOfCells(), max(counts + [1]), 4))
    planes[:, :, 3] = 1.0
    slot = np.zeros(len(cell), dtype=int)
    for i in range(1, len(cell)):
        slot[i] = slot[i - 1] + 1 if cell[i] == cell[i - 1] else 0
    planes[cell, slot, :3] = normal
    planes[cell, slot, 3] = (normal * middle).sum(axis=1)
    return cell, area, normal, middle, planes, lo_box, hi_box


def uncovered(query, planes, lo_box, hi_box):
    """For each query point (Q, 3): True where no cell holds it. Cells are binned on a grid of
    about one cell per bin by their bounding boxes; each bin's points are tested against its
    cells' half-spaces at once."""
    n = len(planes)
    g = max(1, int(round(n ** (1.0 / 3.0))))
    lo = np.array([bounds[0], bounds[2], bounds[4]])
    step = np.maximum((np.array([bounds[1], bounds[3], bounds[5]]) - lo) / g, 1e-300)

    def bin_of(x):
        return np.clip(np.floor((x - lo) / step).astype(int), 0, g - 1)

    members = {}
    b0, b1 = bin_of(lo_box), bin_of(hi_box)
    for c in range(n):
        for i in range(b0[c, 0], b1[c, 0] + 1):
            for j in range(b0[c, 1], b1[c, 1] + 1):
                for k in range(b0[c, 2], b1[c, 2] + 1):
                    members.setdefault((i * g + j) * g + k, []).append(c)
    qb = bin_of(query)
    key = (qb[:, 0] * g + qb[:, 1]) * g + qb[:, 2]
    free = np.ones(len(query), dtype=bool)
    tol = 1e-7 * size
    for b in np.unique(key):
        cs = members.get(int(b))
        if not cs:
            continue
        qi = np.nonzero(key == b)[0]
        h = planes[cs]  # (C, M, 4)
        s = np.einsum('cmk,qk->qcm', h[:, :, :3], query[qi]) - h[None, :, :, 3]
        free[qi] &= ~(s.max(axis=2) <= tol).any(axis=1)
    return free


def free_faces():
    """--view free: (azimuth, elevation, why); azimuth None where nothing tells. The model's
    surface is the faces no other block covers: those on the bounding box's planes, and those
    off them where a point 1e-5 of the model's size outside the face's centre lies in no block
    (a slope face, a cut, the walls of removed blocks). Of these, the free faces are, in a
    stability VTU, the exposed blocks' (mode >= 1: each has a free face) off the box or on a
    box side that is mostly exposed blocks' (a side given to slice-stability --free-faces);
    in any other VTU, those off the box (its sides may as well be fixed ones)."""
    cell, area, normal, middle, planes, lo_box, hi_box = faces_of(grid)
    box = np.array(bounds).reshape(3, 2)
    side = np.full(len(cell), -1)  # the box side (2 axis + end) a face lies on, or -1
    for axis in range(3):
        for end in range(2):
            side[(np.abs(normal[:, axis]) > 1 - 1e-9)
                 & (np.abs(middle[:, axis] - box[axis, end]) <= 1e-7 * size)] = 2 * axis + end
    idx = np.nonzero(side < 0)[0]
    idx = np.concatenate([idx[uncovered(middle[idx] + 1e-5 * size * normal[idx], planes,
                                        lo_box, hi_box)], np.nonzero(side >= 0)[0]])
    choices = []  # (face indices, what they are): the first with a direction is taken
    if stability:
        exposed = vtk_to_numpy(cells.GetArray('mode')) >= 1
        if not exposed.any():
            return None, None, 'no exposed block (mode >= 1)'
        idx = idx[exposed[cell[idx]]]
        whose = 'of the %d exposed blocks' % int(exposed.sum())
        # A box side counts as free (slice-stability --free-faces) if most of it is exposed
        # blocks' (boundary blocks along it are not exposed); other sides are not, but exposed
        # blocks at their edges touch them too. In a coarse model whose cut exposes most
        # blocks, every side is: so the faces off the box (a cut, removed blocks) come first.
        free_side = [area[idx][side[idx] == k].sum()
                     >= 0.5 * area[side == k].sum() > 0 for k in range(6)]
        on_free_side = np.array(free_side + [False])[side[idx]]  # side -1: False
        choices.append((idx[side[idx] < 0], 'free faces off the bounding box ' + whose))
        choices.append((idx[(side[idx] < 0) | on_free_side], 'free faces ' + whose))
    else:
        choices.append((idx[side[idx] < 0], 'free faces off the bounding box'))
    for idx, said in choices:
        if idx.size == 0:
            why = ('no free face' if stability else
                   'no face off the bounding box that no block covers')
            continue
        total = float(area[idx].sum())
        mean = (area[idx, None] * normal[idx]).sum(axis=0)
        length = float(np.linalg.norm(mean))
        said = '%.4g m2 of %s' % (total, said)
        if length >= MIN_MEAN_NORMAL * total:
            break
        why = ('the %s face every way (mean normal %.2g of their area: round a tunnel or '
               'gallery?)' % (said, length / total))
    else:
        if not stability:
            why += '; no stability arrays (slice-stability) either'
        return None, None, why
    u = mean / length
    el = math.degrees(math.asin(max(-1.0, min(1.0, u[2]))))
    facing = math.degrees(math.atan2(u[0], u[1])) % 360.0
    az = None if abs(el) > STEEP else (facing + (FREE_TURN if facing < 180 else -FREE_TURN))
    lo_el, hi_el = FREE_ELEVATION  # from below only for faces that clearly face down
    held = min(max(el, lo_el), hi_el) if el > -lo_el else min(max(el, -hi_el), -lo_el)
    why = ('outside the %s: their mean outward normal points to azimuth %.0f, elevation %.0f'
           % (said, facing, el))
    if az is None:
        az = 141.5  # the South-East's, at the elevation of the free faces
        why += ' (steep: the azimuth of the South-East)'
    else:
        why += ', turned %g towards the South' % FREE_TURN
    return az, held, why


# The first Render() resets the camera, so the camera is placed after it.
Render(view)
if section:  # a 2-D section in (x, z) (docs/2d.md): seen square on, from -y
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[0], centre[1] - 3 * size, centre[2]]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
    view.CameraParallelProjection = 1
    Render(view)
    view.ResetCamera()
    view.CameraParallelScale = 0.36 * size
    seen = 'square on, from -y (a 2-D section)'
else:
    centre[2] -= 0.08 * size  # the base in the picture too
    azimuth = None
    if view_spec[0] == 'angles':
        azimuth, elevation, label = view_spec[1:]
        seen = 'from azimuth %g, elevation %g (--view %s)' % (
            azimuth, elevation, label if label else '%g,%g' % (azimuth, elevation))
    elif view_spec[0] == 'free' or stability:
        azimuth, elevation, why = free_faces()
        flag = '--view free' if view_spec[0] == 'free' else 'a stability VTU'
        seen = ('from azimuth %.0f, elevation %.0f (%s): %s' % (azimuth, elevation, flag, why)
                if azimuth is not None else
                'from the South-East (%s: nothing tells where the free faces are: %s)'
                % (flag, why))
        if azimuth is not None:
            azimuth, elevation = round(azimuth), round(elevation)
    else:
        seen = 'from the South-East'
    view.CameraFocalPoint = centre
    if azimuth is None:  # today's camera, as it was
        view.CameraPosition = [c + s * size for c, s in zip(centre, SOUTH_EAST)]
        view.CameraViewUp = [0, 0, 1]
    else:  # another direction, at the distance that fits the model in
        a = math.radians(azimuth)
        up = [0, 0, 1]
        if abs(elevation) > 89.9:  # straight down (or up): screen up is the far side
            up = [-math.copysign(1, elevation) * math.sin(a),
                  -math.copysign(1, elevation) * math.cos(a), 0]
        step = fitted(offset(azimuth, elevation), up)
        view.CameraPosition = [c + s for c, s in zip(centre, step)]
        view.CameraViewUp = up
    view.CameraViewAngle = 30
Render(view)
look = np.array(view.CameraFocalPoint) - np.array(view.CameraPosition)
look /= np.linalg.norm(look)
if not SaveScreenshot(picture, view, ImageResolution=[1000, 620], CompressionLevel='9'):
    bad('%s: ParaView could not write the picture' % picture)
print('render.py: %s -> %s: coloured by %s; seen %s; looking along (%.6f, %.6f, %.6f)'
      % (blocks_file, picture, colouring, seen, look[0], look[1], look[2]))
