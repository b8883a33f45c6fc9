"""Checks the two solves saved by abort_keep_resume.xml (after
abort_setup.py): the aborted one and the one Apply continued.

- Aborted: every point still has a value (the earlier 32 walks at least,
  more where the aborted solve got to), none NaN, the gradient finite
  everywhere (ParaView's Stream Tracer ran on it), some points short of the
  8192 walks (array WalkCount), and the field data says so.
- Continued: every point has 8192 walks, and the numbers are bit for bit
  those of one uninterrupted Python solve of the same scene, which they are
  only if Apply continued every point from the walks it held.

    PYTHONPATH=BUILD/lib/python3.11/site-packages python3 check_gui_abort.py DIR"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

from gui_scene import solver_on_the_scene  # noqa: E402

WALKS, EARLIER = 8192, 32


def read(name):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(os.path.join(sys.argv[1], name))
    reader.Update()
    out = reader.GetOutput()
    assert out.GetNumberOfPoints() == 100, (name, out.GetNumberOfPoints())
    return out


def values(data, name):
    array = data.GetPointData().GetArray(name)
    assert array is not None, name
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


aborted = read("gui_aborted.vtp")
g = values(aborted, "g")
assert not any(math.isnan(v) for v in g), "NaN values after the abort"
assert all(math.isfinite(v) for v in values(aborted, "g_Gradient"))
counts = values(aborted, "WalkCount")
assert min(counts) >= EARLIER, min(counts)
short = sum(1 for c in counts if c < WALKS)
assert 0 < short < 100, short
fd = aborted.GetFieldData()
assert fd.GetArray("TotalWalks").GetValue(0) == sum(counts)

resumed = read("gui_resumed.vtp")
assert resumed.GetPointData().GetArray("WalkCount") is None  # all walks, none short

# The same scene in plain VTK, solved in one go.
solver = solver_on_the_scene(half_width=0.6, resolution=9, triangulate=True)
solver.ComputeGradientOn()
solver.SetWalksPerPoint(WALKS)
solver.Update()
python = solver.GetOutput()
for name in ("g", "g_Variance", "g_Gradient"):
    a, b = values(resumed, name), values(python, name)
    worst = max(abs(x - y) for x, y in zip(a, b))
    assert worst == 0.0, (name, worst)
print("ok: Abort kept every point's walks (%d of 100 short of %d, none NaN, the gradient "
      "finite), and Apply continued them to one solve's numbers bit for bit" % (short, WALKS))
