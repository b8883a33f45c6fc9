"""pvbatch: the Walk On Spheres Solver with an implicit boundary chosen as in
the GUI (Implicit Boundary property), no Boundary input, values from an
expression: ParaView's own Sphere (|x - c|^2 - r^2, Lipschitz Bound 2r) and
the plugin's Signed Distance Sphere and Signed Distance Box (Lipschitz
Bound 1) against the closed form of a harmonic function."""
import math
import sys

import paraview.simple as pvs
from paraview import servermanager

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")

CENTER = (0.3, -0.2, 0.1)
RADIUS = 1.2
EXPRESSION = "x*x - y*y + 0.5*z"


def exact(x, y, z):
    return x * x - y * y + 0.5 * z


def check(solver, label, points):
    """|z| < 5 at every point, mean z^2 within loose limits, no NaN."""
    solver.UpdatePipeline()
    data = servermanager.Fetch(solver)
    assert data.GetNumberOfPoints() == points, (label, data.GetNumberOfPoints())
    mean = data.GetPointData().GetArray("Solution")
    variance = data.GetPointData().GetArray("Solution_Variance")
    assert mean is not None and variance is not None, label
    worst, sum_z2, spread = 0.0, 0.0, 0.0
    for i in range(points):
        x, y, z = data.GetPoint(i)
        value = mean.GetTuple1(i)
        assert math.isfinite(value), (label, i)
        score = (value - exact(x, y, z)) / math.sqrt(variance.GetTuple1(i))
        worst = max(worst, abs(score))
        sum_z2 += score * score
        spread = max(spread, abs(exact(x, y, z)))
    assert worst < 5.0, (label, worst)
    assert 0.4 < sum_z2 / points < 2.0, (label, sum_z2 / points)
    # The check has teeth: the solution varies far more than its error.
    assert spread > 0.3, (label, spread)
    print("ok: %s, %d points, max |z| = %.2f, mean z^2 = %.2f"
          % (label, points, worst, sum_z2 / points))


# Probe: points of a small sphere surface (and its center) inside the boundary.
probe = pvs.Sphere(Center=list(CENTER), Radius=0.8, ThetaResolution=8, PhiResolution=6)
probe.UpdatePipeline()
points = probe.GetDataInformation().GetNumberOfPoints()

# paraview.simple would connect the active source (the probe) to the first
# input, Boundary: leave it empty explicitly, as a GUI user would.
solver = pvs.WalkOnSpheresSolver(Boundary=None, Probe=probe)
# (Boundary takes several surfaces: its value is a list, here empty.)
assert not solver.Boundary
assert solver.ImplicitBoundary.GetXMLLabel() == "None"  # the default
assert abs(solver.LipschitzBound - 1.0) < 1e-15
available = solver.GetProperty("ImplicitBoundary").Available
for name in ("None", "Plane", "Sphere", "Box", "Cylinder", "Signed Distance Sphere",
             "Signed Distance Box", "Signed Distance Rounded Box", "Signed Distance Torus",
             "Signed Distance Cylinder", "Signed Distance Capsule", "Signed Distance Plane"):
    assert name in available, (name, available)

solver.BoundaryValueExpression = EXPRESSION
solver.WalksPerPoint = 256
solver.Seed = 3

# ParaView's Sphere: |x - c|^2 - r^2 changes as fast as 2r inside.
solver.ImplicitBoundary = "Sphere"
solver.ImplicitBoundary.Center = list(CENTER)
solver.ImplicitBoundary.Radius = RADIUS
solver.LipschitzBound = 2.0 * RADIUS
check(solver, "ParaView Sphere", points)

# The exact signed distance: Lipschitz Bound 1.
solver.ImplicitBoundary = "Signed Distance Sphere"
solver.ImplicitBoundary.Center = list(CENTER)
solver.ImplicitBoundary.Radius = RADIUS
solver.LipschitzBound = 1.0
check(solver, "Signed Distance Sphere", points)

solver.ImplicitBoundary = "Signed Distance Box"
solver.ImplicitBoundary.Center = list(CENTER)
solver.ImplicitBoundary.HalfExtents = [1.0, 0.9, 1.1]
check(solver, "Signed Distance Box", points)

# An invalid radius is an error (the output is the bare probe), not a crash;
# the pipeline runs again once it is fixed.
solver.ImplicitBoundary = "Signed Distance Sphere"
solver.ImplicitBoundary.Radius = -1.0
solver.UpdatePipeline()
bare = servermanager.Fetch(solver)
assert bare.GetPointData().GetArray("Solution") is None
solver.ImplicitBoundary.Radius = RADIUS
check(solver, "Signed Distance Sphere again", points)
print("ok: implicit boundaries through the plugin")

# CSG as in the GUI: a ball with two holes, one a sphere surface grouped with
# it by Group Datasets, one a Signed Distance Sphere (Difference removes all
# other operands from the first block). The harmonic polynomial is exact in
# any domain, so this checks that the walks stop on the combined surface and
# that no probe point is mistaken for an outside one.
ball = pvs.Sphere(Center=[0.0, 0.0, 0.0], Radius=1.2, ThetaResolution=64, PhiResolution=64)
hole = pvs.Sphere(Center=[0.5, 0.0, 0.0], Radius=0.3, ThetaResolution=32, PhiResolution=32)
group = pvs.GroupDatasets(Input=[ball, hole])
cloud = pvs.Sphere(Center=[0.0, 0.0, 0.0], Radius=0.9, ThetaResolution=8, PhiResolution=6)
cloud.UpdatePipeline()
csg_points = cloud.GetDataInformation().GetNumberOfPoints()
csg = pvs.WalkOnSpheresSolver(Boundary=group, Probe=cloud)
assert "Union" in csg.GetProperty("CSGOperation").Available
csg.CSGOperation = "Difference"
csg.ImplicitBoundary = "Signed Distance Sphere"
csg.ImplicitBoundary.Center = [-0.5, 0.0, 0.0]
csg.ImplicitBoundary.Radius = 0.3
csg.BoundaryValueExpression = EXPRESSION
csg.WalksPerPoint = 256
csg.Seed = 5
check(csg, "ball minus a grouped sphere minus a Signed Distance Sphere", csg_points)
escaped = servermanager.Fetch(csg).GetPointData().GetArray("EscapedFraction")
assert escaped is None or escaped.GetRange()[1] == 0.0, escaped.GetRange()
print("ok: CSG of grouped surfaces and an implicit function through the plugin")
