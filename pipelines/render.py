# Renders blocks.vtu (slice-export --format vtu) to a PNG with ParaView, blocks coloured by
# volume (log scale), removed blocks absent (they are not in the file), joints optional.
#   pvpython pipelines/render.py blocks.vtu picture.png [joints.vtu]
# It needs an X server (Debian's ParaView renders through GLX only): pipelines/render starts its
# own Xvfb, finds a pvpython and turns failures into one line. Bad input: one line on stderr
# starting "render.py: error:", exit 1.
import os
import sys

# An unpacked python3-paraview (pipelines/render) comes second on pvpython's path, after the
# system's dist-packages where python3-vtk9 keeps an incompatible vtkmodules: put the
# directories of PYTHONPATH first again.
first = [p for p in os.environ.get('PYTHONPATH', '').split(':') if p]
sys.path = first + [p for p in sys.path if p not in first]

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,  # noqa: E402
                             GetScalarBar, Render, SaveScreenshot, Show,
                             XMLUnstructuredGridReader)



def bad(what):
    print('render.py: error: ' + what, file=sys.stderr)
    sys.exit(1)


if len(sys.argv) not in (3, 4):
    bad('usage: pvpython render.py blocks.vtu picture.png [joints.vtu]')
blocks_file, picture = sys.argv[1], sys.argv[2]
for f in sys.argv[1:2] + sys.argv[3:]:
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
shown = Show(blocks, view)
shown.Representation = 'Surface With Edges'
shown.EdgeColor = [0.15, 0.15, 0.15]
ColorBy(shown, ('CELLS', 'volume'))
lut = GetColorTransferFunction('volume')
lut.ApplyPreset('Viridis (matplotlib)', True)
lo, hi = blocks.CellData['volume'].GetRange()
lut.RescaleTransferFunction(lo, hi)
if lo > 0 and hi > 10 * lo:  # volumes span decades: a log scale shows them all
    lut.MapControlPointsToLogSpace()
    lut.UseLogScale = 1
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view)
bar.Title = 'block volume [m3]'
bar.ComponentTitle = ''
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = bar.LabelFontSize = 14

if len(sys.argv) == 4:
    joints = XMLUnstructuredGridReader(FileName=[sys.argv[3]])
    j = Show(joints, view)
    j.DiffuseColor = j.AmbientColor = [0.8, 0.2, 0.1]
    j.Opacity = 0.25

# Looking from the South-East, above: x East, y North, z Up. The first Render() resets the
# camera, so the camera is placed after it.
Render(view)
bounds = blocks.GetDataInformation().GetBounds()
centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
if bounds[2] == bounds[3]:  # a 2-D section in (x, z) (docs/2d.md): seen square on, from -y
    bar.Title = 'block area [m2]'
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[0], centre[1] - 3 * size, centre[2]]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
    view.CameraParallelProjection = 1
    Render(view)
    view.ResetCamera()
    view.CameraParallelScale = 0.36 * size
else:
    centre[2] -= 0.08 * size  # the base in the picture too
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[0] + 1.35 * size, centre[1] - 1.7 * size,
                           centre[2] + 1.1 * size]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
Render(view)
if not SaveScreenshot(picture, view, ImageResolution=[1000, 620], CompressionLevel='9'):
    bad('%s: ParaView could not write the picture' % picture)
print('render.py: %s -> %s' % (blocks_file, picture))
