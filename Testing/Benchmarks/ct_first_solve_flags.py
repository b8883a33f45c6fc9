"""Benchmark (not part of the tests): how many points does the CT workflow's
default solve (Documentation/Examples/ct_workflow.py) flag unreliable, seed
after seed, under each source sampling? Each flagged point is a warning in
ParaView; the time per solve is printed too.

    pvbatch ct_first_solve_flags.py [--seeds 20]
"""
import argparse
import os
import sys
import time

from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
import ct_workflow  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--seeds", type=int, default=20)
args = parser.parse_args()

p = ct_workflow.build_pipeline(os.path.join(ct_workflow.data_folder(), ct_workflow.VOLUME_NAME))
solver = p["solver"]
for sampling in ["Green's Function", "Source Density"]:
    solver.SourceSampling = sampling
    counts = []
    start = time.time()
    for seed in range(args.seeds):
        solver.Seed = seed
        solver.UpdatePipeline()
        reliable = servermanager.Fetch(solver).GetPointData().GetArray("T_VarianceReliable")
        counts.append(sum(1 for i in range(reliable.GetNumberOfTuples())
                          if reliable.GetValue(i) == 0))
    print("%s: flagged per seed %s, %d in all; %.2f s a solve" % (
        sampling, counts, sum(counts), (time.time() - start) / args.seeds))
