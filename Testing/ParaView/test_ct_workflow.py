"""pvbatch: the CT workflow of Documentation/Examples/ct_workflow.py, small.

Runs it headless as the demo does (volume -> padded -> contour -> solver on a
Slice with the volume as the Poisson source -> streamlines and glyphs ->
picture), then checks what a user relies on:
  - the slice carries T, T_Variance and T_Gradient; the streamlines and the
    glyphs are not empty;
  - the heat source raises the temperature: T minus the Laplace solution
    (same inputs, no source) is positive on average inside the head by more
    than 5 standard errors (a wrong source sign fails);
  - the maximum principle: with heating (f <= 0), T is nowhere below the
    skin's coldest temperature by more than 5 standard deviations;
  - dragging the slice plane and re-applying: the solver, the streamlines and
    the glyphs follow the new plane.
The picture is checked for being rendered by check_picture_panels.py.

    pvbatch test_ct_workflow.py OUTPUT_FOLDER
"""
import math
import os
import sys

from paraview import servermanager

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "Documentation", "Examples"))
import ct_workflow  # noqa: E402

output = sys.argv[1]
p = ct_workflow.run_headless(ct_workflow.parse_arguments(
    ["--output", output, "--walks", "16", "--seed", "5"]))
solver = p["solver"]


def fetch_arrays(proxy, names):
    data = servermanager.Fetch(proxy)
    arrays = [data.GetPointData().GetArray(n) for n in names]
    assert all(a is not None for a in arrays), (names, data.GetPointData())
    return data, arrays


sliced, (t, var, grad, ct) = fetch_arrays(solver, ["T", "T_Variance", "T_Gradient", "MetaImage"])
n = sliced.GetNumberOfPoints()
assert n > 1000, n
assert grad.GetNumberOfComponents() == 3
assert p["streamlines"].GetDataInformation().GetNumberOfPoints() > 1000
assert p["glyphs"].GetDataInformation().GetNumberOfCells() > 100
inside = [i for i in range(n) if ct.GetTuple1(i) >= ct_workflow.SKIN_ISO_VALUE]
assert len(inside) > 500, len(inside)

# The maximum principle with heating.
p["boundary"].UpdatePipeline()
coldest = p["boundary"].PointData["T"].GetRange()[0]
for i in inside:
    value, sigma = t.GetTuple1(i), math.sqrt(var.GetTuple1(i))
    assert math.isfinite(value), i
    assert value >= coldest - 5.0 * sigma - 1e-9, (i, value, coldest, sigma)

# Heating raises T: against the Laplace solution of the same slice.
heated = [t.GetTuple1(i) for i in inside]
heated_var = [var.GetTuple1(i) for i in inside]
solver.Equation = "Laplace"  # warns that the source is ignored: expected
_, (t0, var0) = fetch_arrays(solver, ["T", "T_Variance"])
difference = sum(heated[k] - t0.GetTuple1(i) for k, i in enumerate(inside)) / len(inside)
stderr = math.sqrt(sum(heated_var[k] + var0.GetTuple1(i)
                       for k, i in enumerate(inside))) / len(inside)
print("heating raises T inside by %.3f (standard error %.3f)" % (difference, stderr))
assert difference > 5.0 * stderr, (difference, stderr)
solver.Equation = "Poisson"

# Drag the slice down to z = 50 and re-apply: everything downstream follows.
origin = list(p["slice"].SliceType.Origin)
p["slice"].SliceType.Origin = [origin[0], origin[1], 50.0]
moved, (t1,) = fetch_arrays(solver, ["T"])
zs = {round(moved.GetPoint(i)[2], 9) for i in range(moved.GetNumberOfPoints())}
assert zs == {50.0}, sorted(zs)[:5]
for key in ("streamlines", "glyphs"):
    p[key].UpdatePipeline()
    bounds = p[key].GetDataInformation().GetBounds()
    # Streamlines lie in the plane; arrows stick out of it along T_Gradient.
    assert abs(0.5 * (bounds[4] + bounds[5]) - 50.0) < 5.0, (key, bounds)
assert int(solver.FieldData["ProbePoints"].GetRange()[0]) == moved.GetNumberOfPoints()
print("ok: CT workflow: %d slice points, %d inside; the slice moved to z = 50 and the "
      "solver, streamlines and glyphs followed" % (n, len(inside)))
