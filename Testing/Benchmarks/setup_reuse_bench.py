"""What a built problem saves: the time of updates that need no new boundary.

Prints two tables (one run, this machine):

1. The Walk On Spheres Stream Tracer with 16 seeds inside a 1.31M-triangle
   bumpy sphere (an icosahedron subdivided 8 times onto the unit sphere, radius
   1 + 0.15 sin 6x sin 6y sin 6z, as the C++ benchmark's): it estimates the
   gradient at every integration stage, which built the boundary anew each time
   before the solver kept it between updates.
2. The solver on a mesh given with --mesh (for example the 1.9M-triangle soup
   LIDC2_iso10.5_raw.vtp): the first update, then one after the probe plane
   moved, then one with more walks. Only the first should build the hierarchy.
3. With --ct-skin (Data/headsq_skin_iso500_closed.vtp): every GridFree filter
   that solves, first update and a second one after its probe (seeds,
   domain) moved, whether each built its boundary. The 3D filters run on the
   skin; the 2D ones (cross field, deformation, diffusion curves) on the
   skin's contour in the plane through its centre.

Runs against any build of the `gridfree` package on PYTHONPATH (older builds
report no LastBoundaryBuilt). Not a test: run by hand, e.g.
  PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 \\
      Testing/Benchmarks/setup_reuse_bench.py --mesh LIDC2_iso10.5_raw.vtp
"""
import argparse
import math
import os
import random
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPlane  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkCutter, vtkStripper  # noqa: E402
from vtkmodules.vtkFiltersModeling import vtkLinearSubdivisionFilter  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkPlatonicSolidSource  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

from gridfree_testing import point_cloud  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def bumpy_sphere(levels=8, amplitude=0.15, frequency=6.0):
    """20 * 4**levels triangles; T = x^2 - y^2 on its vertices."""
    ico = vtkPlatonicSolidSource()
    ico.SetSolidTypeToIcosahedron()
    sub = vtkLinearSubdivisionFilter()
    sub.SetInputConnection(ico.GetOutputPort())
    sub.SetNumberOfSubdivisions(levels)
    sub.Update()
    mesh = vtkPolyData()
    mesh.DeepCopy(sub.GetOutput())
    mesh.GetPointData().Initialize()
    points = mesh.GetPoints()
    values = vtkDoubleArray()
    values.SetName("T")
    values.SetNumberOfTuples(points.GetNumberOfPoints())
    for i in range(points.GetNumberOfPoints()):
        x, y, z = points.GetPoint(i)
        n = math.sqrt(x * x + y * y + z * z)
        x, y, z = x / n, y / n, z / n
        r = 1.0 + amplitude * math.sin(frequency * x) * math.sin(frequency * y) * \
            math.sin(frequency * z)
        x, y, z = r * x, r * y, r * z
        points.SetPoint(i, x, y, z)
        values.SetValue(i, x * x - y * y)
    mesh.GetPointData().AddArray(values)
    return mesh


def timed_update(algorithm):
    start = time.perf_counter()
    algorithm.Update()
    return time.perf_counter() - start


def stream_tracer_table(threads):
    mesh = bumpy_sphere()
    rng = random.Random(5)
    seeds = []
    while len(seeds) < 16:
        p = [rng.uniform(-0.5, 0.5) for _ in range(3)]
        if sum(c * c for c in p) < 0.25:
            seeds.append(p)
    tracer = gridfree.vtkWalkOnSpheresStreamTracer()
    tracer.SetBoundaryData(mesh)
    tracer.SetSeedsData(point_cloud(seeds))
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    tracer.SetWalksPerPoint(256)
    tracer.SetNumberOfThreads(threads)
    tracer.SetStepLength(0.02)
    tracer.SetStepLengthIsRelative(False)
    tracer.SetMaximumPropagation(0.2)
    tracer.SetMaximumNumberOfSteps(10)
    seconds = timed_update(tracer)
    estimates = tracer.GetLastNumberOfEstimates()
    lines = tracer.GetOutput().GetNumberOfLines()
    print("\nStream tracer, 16 seeds, 256 walks per estimate, %d thread(s), "
          "bumpy sphere of %d triangles" % (threads, mesh.GetNumberOfPolys()))
    print("| update (s) | gradient estimates | lines | s per estimate |")
    print("|---:|---:|---:|---:|")
    print("| %.2f | %d | %d | %.4f |" % (seconds, estimates, lines,
                                          seconds / max(estimates, 1)))


def solver_table(path, threads):
    mesh = read_with_values(path)
    b = mesh.GetBounds()
    zmin, zmax = b[4], b[5]
    centre = [(b[2 * k] + b[2 * k + 1]) / 2 for k in range(3)]
    plane = vtkPlaneSource()
    plane.SetResolution(40, 40)

    def place(z):
        plane.SetOrigin(b[0], b[2], z)
        plane.SetPoint1(b[1], b[2], z)
        plane.SetPoint2(b[0], b[3], z)

    place(centre[2])
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(mesh)
    solver.SetProbeConnection(plane.GetOutputPort())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(16)
    solver.SetNumberOfThreads(threads)
    built = getattr(solver, "GetLastBoundaryBuilt", None)
    print("\nSolver on %s (%d triangles), 41x41 plane, %d thread(s)" % (
        path.split("/")[-1], mesh.GetNumberOfPolys(), threads))
    print("| update | seconds | solve seconds | boundary built |")
    print("|---|---:|---:|---|")
    rows = [("first", None), ("plane moved", lambda: place(centre[2] + 0.05 * (zmax - zmin))),
            ("64 walks", lambda: solver.SetWalksPerPoint(64))]
    for label, change in rows:
        if change:
            change()
        seconds = timed_update(solver)
        print("| %s | %.2f | %.2f | %s |" % (label, seconds, solver.GetLastSolveSeconds(),
                                             "yes" if built is None or built() else "no"))


def read_with_values(path):
    """The surface with T = its height scaled to [0, 1] on the points."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    mesh = vtkPolyData()
    mesh.ShallowCopy(reader.GetOutput())
    b = mesh.GetBounds()
    values = vtkDoubleArray()
    values.SetName("T")
    values.SetNumberOfTuples(mesh.GetNumberOfPoints())
    for i in range(mesh.GetNumberOfPoints()):
        values.SetValue(i, (mesh.GetPoint(i)[2] - b[4]) / (b[5] - b[4]))
    mesh.GetPointData().AddArray(values)
    return mesh


def contour_of(mesh):
    """The mesh cut by the plane z = its centre: closed polylines in one
    z-plane, with the mesh's point arrays interpolated."""
    b = mesh.GetBounds()
    plane = vtkPlane()
    plane.SetOrigin(0.0, 0.0, (b[4] + b[5]) / 2)
    plane.SetNormal(0.0, 0.0, 1.0)
    cutter = vtkCutter()
    cutter.SetInputData(mesh)
    cutter.SetCutFunction(plane)
    stripper = vtkStripper()
    stripper.SetInputConnection(cutter.GetOutputPort())
    stripper.JoinContiguousSegmentsOn()
    stripper.Update()
    curve = vtkPolyData()
    curve.DeepCopy(stripper.GetOutput())
    return curve


def cloud_in(mesh, count, shift, seed=7):
    """`count` points spread in the middle half of the mesh's box (in its
    z-centre plane for a curve), moved by `shift` of the box."""
    b = mesh.GetBounds()
    rng = random.Random(seed)
    flat = b[5] - b[4] < 1e-9 * max(b[1] - b[0], 1.0)
    points = []
    for _ in range(count):
        p = [(b[2 * k] + b[2 * k + 1]) / 2 + (rng.uniform(-0.25, 0.25) + shift) *
             (b[2 * k + 1] - b[2 * k]) for k in range(3)]
        if flat:
            p[2] = b[4]
        points.append(p)
    return point_cloud(points)


def filters_table(path, threads):
    skin = read_with_values(path)
    curve = contour_of(skin)
    add_contour_colours(curve)
    target = vtkPolyData()
    target.DeepCopy(curve)
    c = [(curve.GetBounds()[2 * k] + curve.GetBounds()[2 * k + 1]) / 2 for k in range(2)]
    for i in range(target.GetNumberOfPoints()):
        x, y, z = target.GetPoint(i)
        target.GetPoints().SetPoint(i, c[0] + 1.1 * (x - c[0]) - 0.1 * (y - c[1]),
                                    c[1] + 0.1 * (x - c[0]) + 1.1 * (y - c[1]), z)

    # Each filter: its class, the setter of its points, its settings
    # (Set<Name>(value)), the arrays it reads (index, name), where its points
    # lie and how many.
    height = [(0, "T")]
    colours = [(0, "FrontColor"), (1, "BackColor")]
    filters = (
        ("Walk On Spheres Solver (gradient)", gridfree.vtkWalkOnSpheresSolver, "SetProbeData",
         dict(BoundaryData=skin, ComputeGradient=True), height, skin, 400),
        ("Walk On Spheres Stream Tracer", gridfree.vtkWalkOnSpheresStreamTracer, "SetSeedsData",
         dict(BoundaryData=skin, MaximumNumberOfSteps=10), height, skin, 8),
        ("Walk On Spheres Adaptive Sampler", gridfree.vtkWalkOnSpheresAdaptiveSampler,
         "SetDomainData", dict(BoundaryData=skin, InitialSamples=32, MaximumSamples=64), height,
         skin, 2000),
        ("Helmholtz Decomposition", gridfree.vtkWalkOnSpheresHelmholtzDecomposition,
         "SetProbeData", dict(BoundaryData=skin, FieldExpression="y*iHat - x*jHat + (x*z)*kHat"),
         [], skin, 100),
        # (Its singularity search, off here, asks the same kept problem in
        # every batch; on the head's contour it takes minutes.)
        ("Cross Field (no search)", gridfree.vtkWalkOnSpheresCrossField, "SetProbeData",
         dict(BoundaryData=curve, SearchSingularities=False), [], curve, 100),
        ("Deformation", gridfree.vtkWalkOnSpheresDeformation, "SetProbeData",
         dict(SourceData=curve, TargetData=target), [], curve, 100),
        ("Diffusion Curves", gridfree.vtkWalkOnSpheresDiffusionCurves, "SetProbeData",
         dict(BoundaryData=curve), colours, curve, 400))

    print("\nEvery filter that solves, %s: the CT skin (%d triangles) for 3D, "
          "its centre contour (%d segments) for 2D; 64 walks per point" % (
              "%d thread(s)" % threads if threads else "all threads", skin.GetNumberOfPolys(), curve.GetNumberOfCells() and
              sum(curve.GetCell(i).GetNumberOfPoints() - 1
                  for i in range(curve.GetNumberOfCells()))))
    print("| filter | boundary | first update (s) | built | after moving its points (s) | built |")
    print("|---|---|---:|---|---:|---|")
    for name, cls, set_points, settings, arrays, where, count in filters:
        f = cls()
        for key, value in settings.items():
            getattr(f, "Set" + key)(value)
        for index, array in arrays:
            f.SetInputArrayToProcess(index, 0, 0, POINTS, array)
        getattr(f, set_points)(cloud_in(where, count, 0.0))
        f.SetWalksPerPoint(64)
        f.SetNumberOfThreads(threads)
        first = timed_update(f)
        built_first = f.GetLastBoundaryBuilt()
        getattr(f, set_points)(cloud_in(where, count, 0.02))
        second = timed_update(f)
        print("| %s | %s | %.2f | %s | %.2f | %s |" % (
            name, "skin" if where is skin else "contour", first,
            "yes" if built_first else "no", second,
            "yes" if f.GetLastBoundaryBuilt() else "no"))


def add_contour_colours(curve):
    for name, function in (("FrontColor", lambda x, y: x), ("BackColor", lambda x, y: y)):
        values = vtkDoubleArray()
        values.SetName(name)
        values.SetNumberOfTuples(curve.GetNumberOfPoints())
        for i in range(curve.GetNumberOfPoints()):
            x, y, _ = curve.GetPoint(i)
            values.SetValue(i, function(x, y))
        curve.GetPointData().AddArray(values)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", help="a .vtp surface for the solver table")
    parser.add_argument("--threads", type=int, default=0, help="0: all")
    parser.add_argument("--skip-tracer", action="store_true")
    parser.add_argument("--ct-skin", help="Data/headsq_skin_iso500_closed.vtp: every filter's "
                        "first and second update")
    args = parser.parse_args()
    if args.ct_skin:
        filters_table(args.ct_skin, args.threads)
        return
    if not args.skip_tracer:
        stream_tracer_table(args.threads)
    if args.mesh:
        solver_table(args.mesh, args.threads)


if __name__ == "__main__":
    main()
