"""Benchmark (not part of the tests): the CT workflow's slice
(Documentation/Examples/ct_workflow.py: Poisson with the CT volume as source,
gradient on) to a target standard error at every point inside the head,
with a cache estimator (Sphere Cache by default, or Boundary Cache) against
pointwise walks, on a first slice and on slices moved 5 mm apart. Prints a
table.

    pvbatch ct_cache.py [--estimator sphere|boundary] [--target 0.5] [--slices 10]
                        [--pointwise-slices 2] [--walks-per-sphere 128] [--shell 0.02]
                        [--polynomial 6 (the default; 0: none)]

Standard errors are sqrt(T_Variance) over the slice points inside the head
(CT value of tissue), in degrees; seconds are wall-clock seconds of the
solver's update (the first slice's include building the cache; the
boundary's hierarchy is built before, by a first update of both solvers).
The last columns compare the two estimators where both answered: the mean
of z² of their difference, (a − b)² / (var a + var b), near 1 when both are
unbiased and their error bars right."""
import argparse
import math
import os
import sys
import time

import paraview.simple as pvs
from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
import ct_workflow  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--estimator", choices=("sphere", "boundary"), default="sphere")
parser.add_argument("--target", type=float, default=0.5)
parser.add_argument("--slices", type=int, default=10, help="moved slices after the first")
parser.add_argument("--pointwise-slices", type=int, default=2,
                    help="slices (first one included) also solved with pointwise walks")
parser.add_argument("--cache-points", type=int, default=4096)
parser.add_argument("--cache-walks", type=int, default=64)
parser.add_argument("--cache-volume-points", type=int, default=8192)
parser.add_argument("--offset", type=float, default=0.01)
parser.add_argument("--shell", type=float, default=0.02)
parser.add_argument("--walks-per-sphere", type=int, default=128)
parser.add_argument("--source-samples", type=int, default=256)
parser.add_argument("--most", type=int, default=4096, help="the most walks per point")
parser.add_argument("--step", type=float, default=5.0, help="slice spacing (mm)")
parser.add_argument("--polynomial", type=int, default=6,
                    help="degree of the polynomial control variate of both solvers, as the "
                         "workflow runs (0: none)")
args = parser.parse_args()

volume = os.path.join(ct_workflow.data_folder(), "headsq_headCT.mhd")
p = ct_workflow.build_pipeline(volume, walks=128)
solver = p["solver"]
solver.KeepRunningSums = 0
solver.WalksPerPoint = args.most
solver.TargetStandardError = args.target
ct_array = p["volume"].PointData.keys()[0]

pointwise = pvs.WalkOnSpheresSolver(Boundary=p["boundary"], Probe=p["slice"], Source=p["heat"])
pointwise.BoundaryValues = ["POINTS", "T"]
pointwise.Equation = "Poisson"
pointwise.SourceArray = ["POINTS", "f"]
pointwise.ComputeGradient = 1
pointwise.KeepRunningSums = 0
pointwise.WalksPerPoint = args.most
pointwise.TargetStandardError = args.target

solver.Estimator = "Sphere Cache" if args.estimator == "sphere" else "Boundary Cache"
solver.WalksPerSphere = args.walks_per_sphere
solver.CacheSourceSamples = args.source_samples
solver.CachePoints = args.cache_points
solver.WalksPerCachePoint = args.cache_walks
solver.CacheVolumePoints = args.cache_volume_points
solver.CacheOffset = args.offset
solver.CacheShellDistance = args.shell
solver.PolynomialControlVariate = args.polynomial
pointwise.PolynomialControlVariate = args.polynomial


def inside_numbers(proxy):
    out = servermanager.Fetch(proxy)
    pd = out.GetPointData()
    ct = pd.GetArray(ct_array)
    values, variances = pd.GetArray("T"), pd.GetArray("T_Variance")
    cached = pd.GetArray("FromBoundaryCache")
    rows = {}
    for i in range(out.GetNumberOfPoints()):
        if ct.GetValue(i) >= ct_workflow.SKIN_ISO_VALUE:
            rows[i] = (values.GetValue(i), variances.GetValue(i),
                       cached.GetValue(i) if cached else 0)
    fields = out.GetFieldData()
    def field(name):
        a = fields.GetArray(name)
        return a.GetTuple1(0) if a else float("nan")
    return rows, field


def timed_update(proxy):
    t = time.time()
    proxy.UpdatePipeline()
    return time.time() - t


# The boundary's hierarchy first, for both (with a cheap setting).
z0 = p["slice"].SliceType.Origin[2]
if args.polynomial:
    print("Both solvers with the polynomial control variate of degree %d (points outside the "
          "head are NaN for both)." % args.polynomial)
if args.estimator == "sphere":
    print("CT slice, target %.2f degrees at every point inside the head; sphere cache, %d walks "
          "per sphere, %d source samples per point, shell %.3g" % (
              args.target, args.walks_per_sphere, args.source_samples, args.shell))
else:
    print("CT slice, target %.2f degrees at every point inside the head; boundary cache, %d "
          "points x %d walks (%d volume points), offset %.3g, shell %.3g" % (
              args.target, args.cache_points, args.cache_walks, args.cache_volume_points,
              args.offset, args.shell))
print()
print("| slice | z (mm) | estimator | seconds | cache seconds | shell walks | points inside | from cache | cache walks run "
      "| cache size | max std. error | points above target | mean z² (cache vs "
      "pointwise) |")
print("|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
cache_seconds = []
for k in range(args.slices + 1):
    z = z0 + k * args.step
    origin = list(p["slice"].SliceType.Origin)
    origin[2] = z
    p["slice"].SliceType.Origin = origin
    seconds = timed_update(solver)
    rows, field = inside_numbers(solver)
    cache_seconds.append(seconds)
    errors = [math.sqrt(v) for (_, v, _) in rows.values() if v == v]
    above = sum(1 for e in errors if e > args.target)
    z2 = ""
    if k < args.pointwise_slices:
        pw_seconds = timed_update(pointwise)
        pw_rows, _ = inside_numbers(pointwise)
        pw_errors = [math.sqrt(v) for (_, v, _) in pw_rows.values() if v == v]
        scores = [(rows[i][0] - pw_rows[i][0]) ** 2 / (rows[i][1] + pw_rows[i][1])
                  for i in rows if rows[i][1] == rows[i][1] and rows[i][2]]
        differences = [rows[i][0] - pw_rows[i][0] for i in rows
                       if rows[i][1] == rows[i][1] and rows[i][2]]
        z2 = "%.2f (%d points; mean difference %.3f)" % (
            sum(scores) / max(len(scores), 1), len(scores),
            sum(differences) / max(len(differences), 1))
        print("| %d | %.1f | pointwise | %.2f | | | %d | | | | %.3f | %d | |" % (
            k, z, pw_seconds, len(pw_rows), max(pw_errors),
            sum(1 for e in pw_errors if e > args.target)))
    print("| %d | %.1f | %s cache | %.2f | %.2f | %d | %d | %d | %d | %d | %.3f | %d | %s |" % (
        k, z, args.estimator, seconds, field("CacheSeconds"),
        field("WalksRun"), len(rows), sum(1 for r in rows.values() if r[2]),
        field("CacheWalksRun"),
        field("CacheSpheres") if args.estimator == "sphere" else field("CachePoints"),
        max(errors), above, z2))
if len(cache_seconds) > 1:
    print()
    print("first slice %.2f s; moved slices: mean %.2f s, most %.2f s" % (
        cache_seconds[0], sum(cache_seconds[1:]) / len(cache_seconds[1:]),
        max(cache_seconds[1:])))
