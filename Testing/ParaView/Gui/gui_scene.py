"""The scene of solver_setup.py rebuilt in plain VTK, for the checks that
compare a GUI solve with the same solve from Python: a solver with the unit
sphere carrying g = x*y as Boundary (its array g selected) and the Plane's
7 x 7 points as Probe (abort_setup.py's: a triangulated 10 x 10 plane twice
as wide)."""
import gridfree
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersCore import vtkArrayCalculator, vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource


def solver_on_the_scene(half_width=0.4, resolution=6, triangulate=False):
    sphere = vtkSphereSource()
    sphere.SetRadius(1.0)
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(48)
    surface = vtkArrayCalculator()
    surface.SetInputConnection(sphere.GetOutputPort())
    surface.AddCoordinateScalarVariable("coordsX", 0)
    surface.AddCoordinateScalarVariable("coordsY", 1)
    surface.SetFunction("coordsX*coordsY")
    surface.SetResultArrayName("g")
    plane = vtkPlaneSource()
    plane.SetOrigin(-half_width, -half_width, 0.0)
    plane.SetPoint1(half_width, -half_width, 0.0)
    plane.SetPoint2(-half_width, half_width, 0.0)
    plane.SetResolution(resolution, resolution)
    probe = plane
    if triangulate:
        probe = vtkTriangleFilter()
        probe.SetInputConnection(plane.GetOutputPort())
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryConnection(surface.GetOutputPort())
    solver.SetProbeConnection(probe.GetOutputPort())
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "g")
    # The inputs stay alive with the solver (VTK holds the connections).
    return solver
