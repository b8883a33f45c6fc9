"""Benchmark (not part of the tests): on the CT workflow's slice
(Documentation/Examples/ct_workflow.py: Poisson with the CT volume as source,
gradient on), the time to the first image and the time to a given standard
error, fixed walk counts against the target-error mode, and the progressive
preview (Refine Until Target: 128 walks, then rounds of Refine until every
point is at the target). Prints tables.

    pvbatch ct_target_error.py [--target 0.5] [--threads 0] [--polynomial 6]

Standard errors are sqrt(T_Variance) over the slice points inside the head
(CT value of tissue), in degrees; times are wall-clock seconds of the solver's
update, with the boundary's hierarchy built before (except the first row)."""
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
parser.add_argument("--target", type=float, default=0.5)
parser.add_argument("--threads", type=int, default=0)
parser.add_argument("--polynomial", type=int, default=6,
                    help="degree of the polynomial control variate (0: none)")
args = parser.parse_args()

volume = os.path.join(ct_workflow.data_folder(), "headsq_headCT.mhd")
start = time.time()
p = ct_workflow.build_pipeline(volume, walks=128, polynomial=args.polynomial)
solver = p["solver"]
solver.KeepRunningSums = 0
solver.NumberOfThreads = args.threads
solver.UpdatePipeline()
first = time.time() - start


def errors():
    out = servermanager.Fetch(solver)
    pd = out.GetPointData()
    ct = pd.GetArray(p["volume"].PointData.keys()[0])
    var = pd.GetArray("T_Variance")
    count = pd.GetArray("WalkCount")
    errs, walks = [], []
    for i in range(out.GetNumberOfPoints()):
        if ct.GetValue(i) >= ct_workflow.SKIN_ISO_VALUE:
            errs.append(math.sqrt(var.GetValue(i)))
            walks.append(count.GetValue(i) if count else None)
    return errs, walks


def run(walks, target):
    solver.WalksPerPoint = walks
    solver.TargetStandardError = target
    t = time.time()
    solver.UpdatePipeline()
    seconds = time.time() - t
    errs, counts = errors()
    mean_walks = sum(counts) / len(counts) if target > 0 else walks
    return seconds, sum(errs) / len(errs), max(errs), mean_walks


errs, _ = errors()
print("slice points inside the head: %d; first image (reader to solved slice, 128 walks, "
      "hierarchy built): %.2f s; its standard error mean %.3f, max %.3f"
      % (len(errs), first, sum(errs) / len(errs), max(errs)))
print("| mode | walks per point (mean) | seconds | mean std. error | max std. error |")
print("|---|---:|---:|---:|---:|")
for walks in (64, 128, 256, 512, 1024, 2048):
    seconds, mean_err, max_err, _ = run(walks, 0.0)
    print("| fixed %d | %d | %.2f | %.3f | %.3f |" % (walks, walks, seconds, mean_err, max_err))
for cap in (1024, 4096):
    seconds, mean_err, max_err, mean_walks = run(cap, args.target)
    print("| target %g, at most %d | %.0f | %.2f | %.3f | %.3f |"
          % (args.target, cap, mean_walks, seconds, mean_err, max_err))

# The progressive preview as the GUI's Refine Until Target runs it: a first
# picture at 128 walks, then rounds of Refine (each doubling the maximum,
# running only the walks of the points still above the target).
solver.KeepRunningSums = 1
solver.TargetStandardError = args.target
solver.WalksPerPoint = 128
t = time.time()
solver.UpdatePipeline()
elapsed = time.time() - t
solver.UpdatePropertyInformation()
short = solver.GetPropertyValue("PointsShortOfTarget")
errs, _ = errors()
print()
print("| round | walks per point (most) | round seconds | total seconds | points above "
      "target | max std. error |")
print("|---:|---:|---:|---:|---:|---:|")
print("| 0 (first picture) | 128 | %.2f | %.2f | %d | %.3f |" % (elapsed, elapsed, short, max(errs)))
round_number = 0
walks = 128
while short > 0 and walks < (1 << 20):
    round_number += 1
    t = time.time()
    solver.SMProxy.InvokeCommand("Refine")
    solver.UpdatePipeline()
    seconds = time.time() - t
    elapsed += seconds
    solver.UpdatePropertyInformation()
    short = solver.GetPropertyValue("PointsShortOfTarget")
    walks = solver.GetPropertyValue("WalksPerPointInUse")
    errs, _ = errors()
    print("| %d | %d | %.2f | %.2f | %d | %.3f |"
          % (round_number, walks, seconds, elapsed, short, max(errs)))
