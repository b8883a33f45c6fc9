"""Benchmark (not part of the tests): how often does one point of the CT
workflow (Documentation/Examples/ct_workflow.py) miss at 128 walks? A
handful of seeds cannot tell a rare tail from a miscalibrated point; this
solves --copies copies of the point at once (copy k moved by k·--spacing
mm along z, so each has its own walks), --walks walks each, against a
--reference-walk solve of the point itself, and prints the mean z², the
number of |z| > 5 (and how many of them were flagged) and the most
negative and most positive z.

    pvbatch ct_point_copies.py --point 729 [--copies 2000] [--walks 128]
                               [--reference 32768] [--sampling "Source Density"]
"""
import argparse
import math
import os
import sys

import paraview.simple as pvs
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
sys.path.insert(0, HERE)
import ct_workflow  # noqa: E402
import seeded_solves  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--point", type=int, required=True, help="index of a slice point")
parser.add_argument("--copies", type=int, default=2000)
parser.add_argument("--spacing", type=float, default=5e-5, help="mm between copies")
parser.add_argument("--walks", type=int, default=128)
parser.add_argument("--reference", type=int, default=32768, help="walks of the reference")
parser.add_argument("--sampling", default="", help="Source Sampling (default: the solver's)")
args = parser.parse_args()

p = ct_workflow.build_pipeline(os.path.join(ct_workflow.data_folder(), ct_workflow.VOLUME_NAME))
solver = p["solver"]
first = servermanager.Fetch(solver)
x = first.GetPoint(args.point)
if args.sampling:
    solver.SourceSampling = args.sampling
solver.ComputeGradient = 0
solver.Probe = seeded_solves.point_probe(first, [args.point])
reference, reference_var, _ = seeded_solves.solve(solver, args.reference, 99, "T")[0]

points = vtkPoints()
for k in range(args.copies):
    points.InsertNextPoint(x[0], x[1], x[2] + args.spacing * k)
cloud = vtkPolyData()
cloud.SetPoints(points)
copies = pvs.PVTrivialProducer()
copies.GetClientSideObject().SetOutput(cloud)
solver.Probe = copies
z, flagged_misses, misses = [], 0, 0
for (t, v, r) in seeded_solves.solve(solver, args.walks, 1, "T"):
    z.append((t - reference) / math.sqrt(v + reference_var))
    if abs(z[-1]) > 5.0:
        misses += 1
        flagged_misses += 1 if r == 0 else 0
z.sort()
print("CT point %d (%.2f mm from the skin), %d copies within %.2g mm, %d walks each, against %d"
      % (args.point, first.GetPointData().GetArray("BoundaryDistance").GetValue(args.point),
         args.copies, args.spacing * (args.copies - 1), args.walks, args.reference))
print("mean z² %.3f; |z| > 5: %d (%d of them flagged); lowest z %s; highest z %s" % (
    math.fsum(t * t for t in z) / len(z), misses, flagged_misses,
    " ".join("%.1f" % t for t in z[:5]), " ".join("%.1f" % t for t in z[-5:])))
