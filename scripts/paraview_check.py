# Opens a geoscni .pvd in ParaView itself (pvbatch) and renders its last
# frame coloured by damage: the check of issue 6, point 7, on a machine
# where ParaView is installed (Debian's paraview replaces libvtk9-dev, so
# not on the build machine; ../shared/TOOLCHAIN.md).
# Usage: xvfb-run -a pvbatch scripts/paraview_check.py CASE.pvd OUT.png
import sys
from paraview.simple import (PVDReader, Show, Render, SaveScreenshot,
                             GetActiveViewOrCreate, ColorBy, servermanager)

pvd, png = sys.argv[1], sys.argv[2]
reader = PVDReader(FileName=pvd)
times = list(reader.TimestepValues)
reader.UpdatePipeline(times[-1])
data = servermanager.Fetch(reader)
points = data.GetPointData()
names = [points.GetArrayName(i) for i in range(points.GetNumberOfArrays())]
print("%s: %d frames (t = %g .. %g s), %d points, %d cells" %
      (pvd, len(times), times[0], times[-1], data.GetNumberOfPoints(),
       data.GetNumberOfCells()))
print("point arrays: " + ", ".join(names))
damage = points.GetArray("damage")
if damage is None:
    sys.exit("no damage array in the last frame")
print("damage at t = %g s: %.3f .. %.3f" % ((times[-1],) + damage.GetRange()))
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 800]
view.ViewTime = times[-1]
display = Show(reader, view)
ColorBy(display, ("POINTS", "damage"))
display.RescaleTransferFunctionToDataRange(True)
view.CameraPosition = [60, -50, 40]
view.CameraFocalPoint = [20, 10, 8]
view.CameraViewUp = [0, 0, 1]
view.ResetCamera()
Render(view)
SaveScreenshot(png, view)
print("wrote " + png)
