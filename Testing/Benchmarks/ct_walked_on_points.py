"""Benchmark (not part of the tests): are the error bars right at the points
of the CT workflow's default solve (Documentation/Examples/ct_workflow.py:
4,096 slice points, 128 walks, gradient on) that walk on because their error
bar could not be trusted at 128 walks (Walk On Where Unreliable, 4 by
default)?

Solves the slice with --seeds seeds, with walking on (the default) and
without (1); keeps each (point, seed) that walked on; solves those points
again with --reference walks; and prints, for the kept pairs, the mean z²,
the largest |z| and the flags of the solve without walking on and of the
solve with it, with z = (T − reference) / sqrt(var + reference var).

    pvbatch ct_walked_on_points.py [--seeds 20] [--reference 32768]
"""
import argparse
import math
import os
import sys

from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
sys.path.insert(0, HERE)
import ct_workflow  # noqa: E402
import seeded_solves  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--seeds", type=int, default=20)
parser.add_argument("--reference", type=int, default=32768, help="walks of the reference")
args = parser.parse_args()

p = ct_workflow.build_pipeline(os.path.join(ct_workflow.data_folder(), ct_workflow.VOLUME_NAME))
solver = p["solver"]
factor = solver.WalkOnWhereUnreliable


def slice_solve(walk_on, seed):
    solver.WalkOnWhereUnreliable = walk_on
    solver.Seed = seed
    solver.UpdatePipeline()
    return servermanager.Fetch(solver)


kept = []  # (point, seed, (T, var, reliable) without walking on, the same with, walks)
first = None
for seed in range(args.seeds):
    walked = slice_solve(factor, seed)
    first = first or walked
    a = walked.GetPointData()
    counts = a.GetArray("WalkCount")
    if counts is None:
        continue
    ids = [i for i in range(walked.GetNumberOfPoints()) if counts.GetValue(i) > 128]
    with_ = [(a.GetArray("T").GetValue(i), a.GetArray("T_Variance").GetValue(i),
              a.GetArray("T_VarianceReliable").GetValue(i), counts.GetValue(i)) for i in ids]
    b = slice_solve(1, seed).GetPointData()
    without = [(b.GetArray("T").GetValue(i), b.GetArray("T_Variance").GetValue(i),
                b.GetArray("T_VarianceReliable").GetValue(i)) for i in ids]
    for i, w, o in zip(ids, with_, without):
        kept.append((i, seed, o, w))

print("CT workflow, default solve, %d seeds: %d (point, seed) pairs walked on (factor %d)" % (
    args.seeds, len(kept), factor))
if not kept:
    sys.exit(0)
points = sorted({i for i, _, _, _ in kept})
solver.WalkOnWhereUnreliable = factor
solver.Probe = seeded_solves.point_probe(first, points)
solver.ComputeGradient = 0
reference = dict(zip(points, seeded_solves.solve(solver, args.reference, 99, "T")))


def z(value, variance, ref):
    return (value - ref[0]) / math.sqrt(variance + ref[1])


print("| solve | pairs | mean z² | largest \\|z\\| | flagged | missed (\\|z\\| > 5, unflagged) |")
print("|---|---:|---:|---:|---:|---:|")
for name, pick in (("128 walks, no walking on", lambda o, w: o[:3]),
                   ("walking on (default)", lambda o, w: w[:3])):
    zs = [z(*pick(o, w)[:2], reference[i]) for i, _, o, w in kept]
    flags = sum(1 for _, _, o, w in kept if pick(o, w)[2] == 0)
    misses = sum(1 for (_, _, o, w), x in zip(kept, zs) if pick(o, w)[2] == 1 and abs(x) > 5.0)
    print("| %s | %d | %.2f | %.2f | %d | %d |" % (
        name, len(zs), math.fsum(x * x for x in zs) / len(zs), max(abs(x) for x in zs), flags,
        misses))
for i, seed, o, w in kept:
    print("point %d, seed %d: walks %d; z %.2f (flag %d) without, %.2f (flag %d) with" % (
        i, seed, w[3], z(o[0], o[1], reference[i]), o[2], z(w[0], w[1], reference[i]), w[2]))
