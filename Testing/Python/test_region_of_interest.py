"""Region of interest (paper Sec. 5.2.5): a window of a probe costs only its
own points. Every point's walks depend on nothing but the seed, the point and
the walk's number, so a small window gives exactly the numbers the whole
image gives at those points, and runs exactly their walks and steps."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData  # noqa: E402
from vtkmodules.vtkImagingCore import vtkExtractVOI  # noqa: E402

from gridfree_testing import sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def image(n=24):
    data = vtkImageData()
    data.SetDimensions(n, n, 1)
    data.SetOrigin(-0.8, -0.8, 0.1)
    data.SetSpacing(1.6 / (n - 1), 1.6 / (n - 1), 1.0)
    return data


def solve(probe):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(sphere_boundary(resolution=24))
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(32)
    solver.Update()
    return solver.GetOutput()


def test_a_window_costs_only_its_points_and_gives_the_same_numbers():
    whole = image()
    voi = vtkExtractVOI()
    voi.SetInputData(whole)
    voi.SetVOI(5, 9, 12, 15, 0, 0)  # 5 x 4 points
    voi.Update()
    window = voi.GetOutput()
    full = solve(whole)
    part = solve(window)
    assert part.GetNumberOfPoints() == 20
    field = part.GetFieldData()
    assert field.GetArray("TotalWalks").GetValue(0) == 20 * 32
    steps = part.GetPointData().GetArray("WalkSteps")
    # TotalSteps is the sum over the window's own points, nothing else.
    assert abs(field.GetArray("TotalSteps").GetValue(0) -
               32 * sum(steps.GetValue(i) for i in range(20))) < 1e-6
    for name in ("T", "T_Variance", "WalkSteps"):
        a, b = part.GetPointData().GetArray(name), full.GetPointData().GetArray(name)
        for i in range(part.GetNumberOfPoints()):
            j = whole.FindPoint(part.GetPoint(i))
            assert a.GetTuple1(i) == b.GetTuple1(j), (name, i)
