"""pvbatch: the GridFree plugin is loaded, its filter runs in a ParaView
pipeline with the boundary array chosen as in the GUI, and the arrays it
produces are right."""
import math
import sys

import paraview.simple as pvs
from paraview import servermanager

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")

sphere = pvs.Sphere(Radius=1.0, ThetaResolution=96, PhiResolution=96)
boundary = pvs.Calculator(Input=sphere, ResultArrayName="T",
                          Function="coordsX*coordsX - coordsY*coordsY")
probe = pvs.Plane(Origin=[-0.5, -0.5, 0.25], Point1=[0.5, -0.5, 0.25],
                  Point2=[-0.5, 0.5, 0.25], XResolution=9, YResolution=9)
solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
solver.BoundaryValues = ["POINTS", "T"]
solver.WalksPerPoint = 256
solver.Seed = 5
solver.UpdatePipeline()

# Defaults and labels as documented.
proxy = servermanager.ProxyManager().GetPrototypeProxy("filters", "WalkOnSpheresSolver")
assert proxy.GetXMLLabel() == "Walk On Spheres Solver", proxy.GetXMLLabel()
fresh = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
assert fresh.WalksPerPoint == 128
assert abs(fresh.Epsilon - 1e-4) < 1e-16
assert fresh.EpsilonIsRelative == 1
assert fresh.NumberOfThreads == 0
assert fresh.ComputeGradient == 0 and fresh.ComputeHessian == 0
assert fresh.ControlVariates == 1
assert list(fresh.DerivativeDirection) == [1.0, 0.0, 0.0]
pvs.Delete(fresh)

info = solver.GetDataInformation()
assert info.GetNumberOfPoints() == 100, info.GetNumberOfPoints()
names = [solver.PointData.keys()][0]
for name in ("T", "T_Variance", "WalkSteps", "EscapedFraction", "TruncatedFraction", "Normals"):
    assert name in names, (name, names)
assert solver.FieldData["TotalWalks"].GetRange()[0] == 25600


def worst_z(data, exact):
    """The largest |estimate − exact| / standard error of T over the points."""
    t = data.GetPointData().GetArray("T")
    var = data.GetPointData().GetArray("T_Variance")
    return max(abs(t.GetTuple1(i) - exact(*data.GetPoint(i))) / math.sqrt(var.GetTuple1(i))
               for i in range(data.GetNumberOfPoints()))


data = servermanager.Fetch(solver)
worst = worst_z(data, lambda x, y, z: x * x - y * y)
assert worst < 5.0, worst
assert data.GetPointData().GetScalars().GetName() == "T"
print("ok: plugin filter ran, max |z| = %.2f" % worst)

# Gradient and Hessian as a ParaView user turns them on: named arrays, the
# gradient as active vectors (what Stream Tracer and Glyph pick up) and the
# Hessian as active tensors (Tensor Glyph), accurate within 5 standard errors.
solver.ComputeGradient = 1
solver.ComputeHessian = 1
solver.UpdatePipeline()
names = solver.PointData.keys()
for name in ("T_Gradient", "T_Gradient_Variance", "T_Hessian", "T_Hessian_Variance",
             "DerivativeStatus"):
    assert name in names, (name, names)
data = servermanager.Fetch(solver)
pd = data.GetPointData()
assert pd.GetVectors().GetName() == "T_Gradient"
assert pd.GetTensors().GetName() == "T_Hessian"
grad, gvar = pd.GetArray("T_Gradient"), pd.GetArray("T_Gradient_Variance")
worst = 0.0
for i in range(data.GetNumberOfPoints()):
    x, y, _ = data.GetPoint(i)
    for k, exact in enumerate((2 * x, -2 * y, 0.0)):
        worst = max(worst, abs(grad.GetComponent(i, k) - exact) / math.sqrt(gvar.GetComponent(i, k)))
assert worst < 5.0, worst
tracer = pvs.StreamTracer(Input=solver, SeedType="Point Cloud")
tracer.Vectors = ["POINTS", "T_Gradient"]
tracer.SeedType.Center = [0.0, 0.0, 0.25]
tracer.SeedType.Radius = 0.2
tracer.SurfaceStreamlines = 1  # the probe is a plane: follow the gradient within it
tracer.UpdatePipeline()
assert tracer.GetDataInformation().GetNumberOfPoints() > 10
print("ok: gradient and Hessian arrays, max |z| of the gradient = %.2f" % worst)

# Progressive refinement as in the GUI: the Refine button doubles the walks,
# only the new ones run, and the output equals one solve with all of them.
solver.ComputeGradient = 0
solver.ComputeHessian = 0
solver.ControlVariates = 0
solver.WalksPerPoint = 64
solver.UpdatePipeline()
assert solver.FieldData["TotalWalks"].GetRange()[0] == 6400
solver.SMProxy.InvokeCommand("Refine")
solver.UpdatePipeline()
assert solver.FieldData["TotalWalks"].GetRange()[0] == 12800
# Only the new walks ran: ParaView hands the filter a fresh shallow copy of
# its input at every update, which must not make the kept sums stale.
assert solver.FieldData["ResumedWalksPerPoint"].GetRange()[0] == 64
refined = servermanager.Fetch(solver)
reference = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
reference.BoundaryValues = ["POINTS", "T"]
reference.WalksPerPoint = 128
reference.Seed = 5
reference.ControlVariates = 0
reference.UpdatePipeline()
once = servermanager.Fetch(reference)
for name in ("T", "T_Variance", "WalkSteps"):
    a, b = refined.GetPointData().GetArray(name), once.GetPointData().GetArray(name)
    assert all(a.GetTuple1(i) == b.GetTuple1(i) for i in range(a.GetNumberOfTuples())), name
print("ok: Refine doubled the walks, same numbers as one solve with 128 walks")

# Streamlines of the gradient, estimated only along the lines: the
# hyperbolas x·y = const of u = x² − y².
seeds = pvs.PointSource(Center=[0.1, 0.5, 0.0], NumberOfPoints=1, Radius=0.0)
tracer = pvs.WalkOnSpheresStreamTracer(Boundary=boundary, Seeds=seeds)
tracer.BoundaryValues = ["POINTS", "T"]
tracer.StepLength = 0.02
tracer.StepLengthIsRelative = 0
tracer.MaximumStreamlineLength = 0.5
tracer.UpdatePipeline()
lines = servermanager.Fetch(tracer)
assert lines.GetNumberOfCells() == 1 and lines.GetNumberOfPoints() > 10
assert lines.GetCellData().GetArray("ReasonForTermination") is not None
assert lines.GetPointData().GetVectors().GetName() == "T_Gradient"
for i in range(lines.GetNumberOfPoints()):
    x, y, z = lines.GetPoint(i)
    assert abs(x * y - 0.05) < 0.03 and abs(z) < 0.03, (x, y, z)
print("ok: stream tracer followed the hyperbola over %d points" % lines.GetNumberOfPoints())

# Two-sided values as set in the GUI: outside the sphere (its front, as
# Sphere winds outward) the front's decaying solution, inside the back's.
sided = pvs.Calculator(Input=boundary, ResultArrayName="Back", Function="1 + coordsX")
points = pvs.PointSource(Center=[0.0, 0.0, 0.0], NumberOfPoints=1, Radius=0.0)
for centre, exact in (([0.3, 0.2, 0.1], lambda x, y, z: 1.0 + x),
                      ([1.6, 0.4, -0.3],
                       lambda x, y, z: (x * x - y * y) / (x * x + y * y + z * z) ** 2.5)):
    points.Center = centre
    two = pvs.WalkOnSpheresSolver(Boundary=sided, Probe=points)
    two.BoundaryValues = ["POINTS", "T"]
    two.TwoSidedBoundaryValues = 1
    two.BackBoundaryValues = ["POINTS", "Back"]
    two.WalksPerPoint = 4096
    two.UpdatePipeline()
    result = servermanager.Fetch(two)
    value = result.GetPointData().GetArray("T").GetTuple1(0)
    sigma = math.sqrt(result.GetPointData().GetArray("T_Variance").GetTuple1(0))
    assert abs(value - exact(*centre)) < 5 * sigma, (centre, value, exact(*centre), sigma)
    pvs.Delete(two)
print("ok: two-sided values, inside and outside")

# The diffusion curves filter: its default image of a 2D curve.
outline = pvs.Line(Point1=[-1.0, 0.0, 0.0], Point2=[1.0, 0.0, 0.0], Resolution=50)
front = pvs.Calculator(Input=outline, ResultArrayName="FrontColor", Function="1")
colours = pvs.Calculator(Input=front, ResultArrayName="BackColor", Function="0")
curves = pvs.WalkOnSpheresDiffusionCurves(Boundary=colours)
curves.FrontColor = ["POINTS", "FrontColor"]
curves.BackColor = ["POINTS", "BackColor"]
curves.ImageResolution = [16, 12]
curves.WalksPerPoint = 16
curves.UpdatePipeline()
image = servermanager.Fetch(curves)
assert image.IsA("vtkImageData") and image.GetDimensions() == (16, 12, 1), image.GetDimensions()
above = image.GetPointData().GetArray("FrontColor").GetTuple1(image.FindPoint(0.0, 0.06, 0.0))
below = image.GetPointData().GetArray("FrontColor").GetTuple1(image.FindPoint(0.0, -0.06, 0.0))
assert above > 0.6 > 0.4 > below, (above, below)
print("ok: diffusion curves image, %.2f above the line and %.2f below" % (above, below))

# Varying coefficients as a ParaView user sets them: Equation "Varying
# Coefficients", an image on the Source port with its conductivity and heat
# arrays chosen by name, a constant absorption. u = x^2 - y^2 + z + 1/2,
# alpha = 2 + x/2, sigma = 1, f = x - u: the cubic B-spline reproduces alpha
# and f exactly (its error for a quadratic is h^2/6 times f's Laplacian, 0).
skin = pvs.Calculator(Input=sphere, ResultArrayName="T",
                      Function="coordsX*coordsX - coordsY*coordsY + coordsZ + 0.5")
voxels = pvs.Wavelet(WholeExtent=[-3, 3, -3, 3, -3, 3])
conductivity = pvs.Calculator(Input=voxels, ResultArrayName="Conductivity",
                              Function="2 + 0.5*coordsX")
heat = pvs.Calculator(Input=conductivity, ResultArrayName="Heat",
                      Function="coordsX - (coordsX*coordsX - coordsY*coordsY + coordsZ + 0.5)")
varying = pvs.WalkOnSpheresSolver(Boundary=skin, Probe=probe, Source=heat)
varying.BoundaryValues = ["POINTS", "T"]
varying.Equation = "Varying Coefficients"
# Off by default in the panel: an image never gives a coefficient unasked.
assert varying.DiffusionFromArray == 0 and varying.SourceTermFromArray == 0
varying.DiffusionFromArray = 1
varying.DiffusionCoefficientArray = ["POINTS", "Conductivity"]
varying.AbsorptionCoefficient = 1.0
varying.SourceTermFromArray = 1
varying.SourceArray = ["POINTS", "Heat"]
varying.ComputeGradient = 1
varying.WalksPerPoint = 512
varying.Seed = 3
varying.UpdatePipeline()
result = servermanager.Fetch(varying)
assert result.GetPointData().GetArray("T_Gradient") is not None
worst = worst_z(result, lambda x, y, z: x * x - y * y + z + 0.5)
assert worst < 5.0, worst
print("ok: varying coefficients from an image's arrays, max |z| = %.2f" % worst)
