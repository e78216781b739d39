# Renders blocks.vtu (slice-export --format vtu) to a PNG with ParaView, removed blocks absent
# (they are not in the file), joints optional:
#   pvpython pipelines/render.py [--view AZ,EL] blocks.vtu picture.png [joints.vtu]
# Colours: a VTU of slice-stability's output (it has the cell array fos) is coloured by factor
# of safety: a diverging map centred on 1, red below (the blocks that fail), blue above, clipped
# to 0..2; blocks that cannot move (fos NaN: not exposed, not removable, stable) light grey.
# Any other VTU is coloured by block volume (log scale).
# Camera: --view AZ,EL looks from azimuth AZ (degrees clockwise from North, +y: 90 looks from
# the East towards the West) and elevation EL (degrees above the horizontal, -90..90). Without
# it, a stability VTU is seen from the side of its exposed blocks (mode >= 1): from the azimuth
# of the horizontal direction from the rock's centre (volume-weighted) to the exposed blocks'
# centre (the mean of their cell centres), 30 degrees up. Where that direction is undefined
# (shorter than 8 % of the model's size: exposed blocks all around, as in a tunnel, or evenly
# over the top of a box), and for any other VTU, the view is from the South-East and above, as
# always. A view other than that one is taken from the distance that fits the model's bounding
# box in. A 2-D section is always seen square on, from -y (--view does not apply).
# It needs an X server (Debian's ParaView renders through GLX only): pipelines/render starts its
# own Xvfb, finds a pvpython and turns failures into one line. Bad input: one line on stderr
# starting "render.py: error:", exit 1. Done: one line on stdout saying what it coloured by and
# from where it looked.
import math
import os
import sys

# An unpacked python3-paraview (pipelines/render) comes second on pvpython's path, after the
# system's dist-packages where python3-vtk9 keeps an incompatible vtkmodules: put the
# directories of PYTHONPATH first again.
first = [p for p in os.environ.get('PYTHONPATH', '').split(':') if p]
sys.path = first + [p for p in sys.path if p not in first]

from paraview import servermanager  # noqa: E402
from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,  # noqa: E402
                             GetScalarBar, Render, SaveScreenshot, Show,
                             XMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkCellCenters  # noqa: E402

USAGE = 'usage: pvpython render.py [--view AZ,EL] blocks.vtu picture.png [joints.vtu]'
# Today's camera, from the South-East and above: the offset from the focal point in units of the
# model's size (azimuth 141.5 degrees, elevation 26.9 degrees).
SOUTH_EAST = (1.35, -1.7, 1.1)
EXPOSED_ELEVATION = 30.0  # degrees: the view from the exposed blocks' side looks down this much
# Of the model's size: a shorter horizontal offset has no direction (data/tunnel.toml: 0.04; the
# slopes of data/: 0.12 to 0.16).
MIN_OFFSET = 0.08
# factor of safety -> colour: ColorBrewer's RdYlBu, red at 0, pale yellow at 1, blue at 2.
FOS_RANGE = (0.0, 2.0)
FOS_POINTS = [0.0, 0.647, 0.0, 0.149,
              0.5, 0.957, 0.427, 0.263,
              1.0, 1.0, 1.0, 0.749,
              1.5, 0.455, 0.678, 0.820,
              2.0, 0.192, 0.212, 0.584]
CANNOT_MOVE = [0.82, 0.82, 0.82]  # NaN: a neutral light grey


def bad(what):
    print('render.py: error: ' + what, file=sys.stderr)
    sys.exit(1)


def parse_view(text):
    """'AZ,EL' in degrees -> (azimuth, elevation); bad input otherwise."""
    parts = text.split(',')
    try:
        az, el = (float(p) for p in parts) if len(parts) == 2 else (None, None)
    except ValueError:
        az = el = None
    if az is None or not math.isfinite(az) or not math.isfinite(el) or not -90 <= el <= 90:
        bad('--view %s: give AZ,EL in degrees, azimuth clockwise from North and elevation '
            '-90..90, e.g. --view 270,30 to look from the West' % text)
    return az % 360.0, el


args, view_angles = [], None
argv = sys.argv[1:]
while argv:
    a = argv.pop(0)
    if a == '--view':
        if not argv:
            bad('--view needs AZ,EL; ' + USAGE)
        view_angles = parse_view(argv.pop(0))
    elif a.startswith('--view='):
        view_angles = parse_view(a[len('--view='):])
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
if blocks.CellData['volume'] is None:
    bad('%s: no cell array "volume"; give blocks.vtu from slice-export --format vtu'
        % blocks_file)
stability = blocks.CellData['fos'] is not None
if stability and blocks.CellData['mode'] is None:
    bad('%s: a cell array "fos" but no "mode"; give the VTU slice-export --format vtu writes '
        'from slice-stability\'s output' % blocks_file)
shown = Show(blocks, view)
shown.Representation = 'Surface With Edges'
shown.EdgeColor = [0.15, 0.15, 0.15]
bounds = blocks.GetDataInformation().GetBounds()
centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])

if stability:
    ColorBy(shown, ('CELLS', 'fos'))
    lut = GetColorTransferFunction('fos')
    lut.ColorSpace = 'Lab'
    lut.RGBPoints = FOS_POINTS
    lut.NanColor = CANNOT_MOVE
    lut.AutomaticRescaleRangeMode = 'Never'  # 0..2 whatever the data: 1 stays in the middle
    lut.RescaleTransferFunction(*FOS_RANGE)
    bar_title = 'factor of safety'
    # The cells, here in pvpython (a few ms for 10^4 blocks): what the camera and the line need.
    grid = servermanager.Fetch(blocks)
    cells = grid.GetCellData()
    fos = vtk_to_numpy(cells.GetArray('fos'))
    mode = vtk_to_numpy(cells.GetArray('mode'))
    volume = vtk_to_numpy(cells.GetArray('volume'))
    movable = fos == fos  # not NaN
    colouring = ('factor of safety (%g..%g, 1 in the middle): %d of %d blocks can move, %d '
                 'below 1, the rest grey' % (FOS_RANGE[0], FOS_RANGE[1], int(movable.sum()),
                                             len(fos), int((fos[movable] < 1).sum())))
else:
    ColorBy(shown, ('CELLS', 'volume'))
    lut = GetColorTransferFunction('volume')
    lut.ApplyPreset('Viridis (matplotlib)', True)
    lo, hi = blocks.CellData['volume'].GetRange()
    lut.RescaleTransferFunction(lo, hi)
    if lo > 0 and hi > 10 * lo:  # volumes span decades: a log scale shows them all
        lut.MapControlPointsToLogSpace()
        lut.UseLogScale = 1
    bar_title = 'block volume [m3]'
    colouring = 'block volume'
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view)
bar.Title = bar_title
bar.ComponentTitle = ''
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = bar.LabelFontSize = 14
if stability:
    bar.DrawNanAnnotation = 1
    bar.NanAnnotation = 'cannot move'
    bar.AddRangeLabels = 1
    bar.RangeLabelFormat = '%-#.2g'

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


def exposed_side():
    """The view from the side of the exposed blocks: (azimuth, why), azimuth None if undefined."""
    exposed = mode >= 1
    if not exposed.any():
        return None, 'no exposed block'
    centres = vtkCellCenters()
    centres.SetInputData(grid)
    centres.Update()
    xyz = vtk_to_numpy(centres.GetOutput().GetPoints().GetData())
    rock = (xyz * volume[:, None]).sum(axis=0) / volume.sum()
    dx, dy = xyz[exposed, :2].mean(axis=0) - rock[:2]
    if math.hypot(dx, dy) < MIN_OFFSET * size:
        return None, ('the exposed blocks surround the rock\'s centre (%.2g of the size from it)'
                      % (math.hypot(dx, dy) / size))
    return math.degrees(math.atan2(dx, dy)) % 360.0, '%d exposed blocks' % int(exposed.sum())


# The first Render() resets the camera, so the camera is placed after it.
Render(view)
if bounds[2] == bounds[3]:  # a 2-D section in (x, z) (docs/2d.md): seen square on, from -y
    bar.Title = 'block area [m2]' if not stability else bar.Title
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
    if view_angles is not None:
        azimuth, elevation = view_angles
        seen = 'from azimuth %g, elevation %g (--view)' % (azimuth, elevation)
    elif stability:
        azimuth, why = exposed_side()
        elevation = EXPOSED_ELEVATION
        seen = ('from azimuth %.0f, elevation %g: the side of the %s' % (azimuth, elevation, why)
                if azimuth is not None else 'from the South-East: %s' % why)
    else:
        azimuth = None
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
if not SaveScreenshot(picture, view, ImageResolution=[1000, 620], CompressionLevel='9'):
    bad('%s: ParaView could not write the picture' % picture)
print('render.py: %s -> %s: coloured by %s; seen %s' % (blocks_file, picture, colouring, seen))
