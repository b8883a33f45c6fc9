"""Benchmark (not part of the tests): are the error bars of the bioheat
solves on the CT head (Documentation/Examples/bioheat_head.py) right, where
the solver flags them unreliable and where it does not?

--sample points of the slice inside the head are solved with --reference
walks (the reference, another seed) and with --walks walks for each of
--seeds seeds; z = (u − reference) / sqrt(var + reference var). Prints, for
the points each solve flags and for the others, the number of z values,
their mean z², the largest |z|, and the misses (|z| > 5, not flagged).
--equation constant is the screened Poisson equation with the brain's k, w
and Q (the comparison solve of the example), varying the tissue table.

    pvbatch ct_bioheat_error_bars.py [--equation constant] [--sample 300]
        [--walks 512] [--seeds 5] [--reference 32768]
"""
import argparse
import builtins
import math
import os
import random
import sys

from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
sys.path.insert(0, HERE)
import bioheat_tissues  # noqa: E402
import seeded_solves  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--equation", choices=("constant", "varying"), default="constant")
parser.add_argument("--sample", type=int, default=300, help="points of the slice checked")
parser.add_argument("--walks", type=int, default=512, help="walks per point of each solve")
parser.add_argument("--seeds", type=int, default=5)
parser.add_argument("--reference", type=int, default=32768, help="walks of the reference")
args = parser.parse_args()
# Made before the pipeline: the tissue table's programmable filter runs in
# this script's namespace and rebinds random, min, max, sum and abs
# (NumPy's), hence builtins below.
sampler = random.Random(5)

p = bioheat_tissues.head_inputs()
inside = servermanager.Fetch(p["inside"])
ids = sampler.sample(range(inside.GetNumberOfPoints()), builtins.min(args.sample, inside.GetNumberOfPoints()))
solver = bioheat_tissues.bioheat_solver(p["skin_u"], seeded_solves.point_probe(inside, ids),
                                        p["tissues"],
                                        constant=args.equation == "constant")
solver.ComputeGradient = 0
solver.TargetStandardError = 0.0


def solve(walks, seed):
    return seeded_solves.solve(solver, walks, seed, "U")


reference = solve(args.reference, 99)
rows = {"flagged": [], "not flagged": []}
for seed in range(1, args.seeds + 1):
    for k, (u, v, r) in enumerate(solve(args.walks, seed)):
        ref, ref_var = reference[k][0], reference[k][1]
        z = (u - ref) / math.sqrt(v + ref_var) if v + ref_var > 0.0 else 0.0
        rows["not flagged" if r == 1 else "flagged"].append(z)

print("bioheat (%s), %d points, reference %d walks, %d seeds of %d walks"
      % (args.equation, len(ids), args.reference, args.seeds, args.walks))
print("| points | z values | mean z² | largest |z| | missed (|z| > 5, not flagged) |")
print("|---|---:|---:|---:|---:|")
for name, z in rows.items():
    if not z:
        print("| %s | 0 | — | — | — |" % name)
        continue
    missed = builtins.sum(1 for x in z if builtins.abs(x) > 5.0) if name == "not flagged" else 0
    print("| %s | %d | %.2f | %.2f | %d |" % (
        name, len(z), math.fsum(x * x for x in z) / len(z), builtins.max(builtins.abs(x) for x in z), missed))
