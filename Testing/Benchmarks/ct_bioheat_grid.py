"""Benchmark (not part of the tests): what a user of a grid solver waits for,
beside the walk. The steady Pennes bioheat equation of ct_bioheat.py (skin at
34 °C, arterial blood at 37 °C, the tissue table of bioheat_tissues.py) is
solved

- on the grid: the whole head at the CT's own resolution (3.2 × 3.2 × 1.5 mm
  voxels), conservative 7-point finite differences with the voxels' sharp
  coefficients (harmonic means of k across faces), every voxel below the
  skin's iso-value held at 34 °C (the staircase a voxel solver sees of the
  skin), by conjugate gradients with a Jacobi preconditioner to a relative
  residual of 1e-8, matrix-free in NumPy;
- by the walk: the slice's points inside the head to a target standard error
  (--target, 0.5 °C by default; target mode takes at least 128 walks per
  point before it trusts an error bar), or with --target 0 a fixed --most
  walks per point, gradient on; wall time, the boundary's hierarchy and the
  coefficients' preparation included;

and prints both times, the grid's unknowns and iterations, and how far the
walk's slice lies from the grid's solution interpolated onto it (the grid is
coarse and its coefficients sharp, the walk's smoothed: their difference
mixes the grid's discretisation error with the smoothing's modelling error).

    pvbatch ct_bioheat_grid.py [--target 0.5] [--most 4096]
    pvbatch ct_bioheat_grid.py --target 0 --most 8     # 8 walks per point
"""
import argparse
# min/max from builtins: pvbatch's Programmable Filter puts VTK's array
# reductions of the same names into the module's globals.
import builtins
import math
import os
import sys
import time

import numpy as np
import paraview.simple as pvs
from paraview import servermanager
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
import bioheat_tissues  # noqa: E402
import ct_workflow  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--target", type=float, default=0.5, help="the walk's standard error (°C)")
parser.add_argument("--most", type=int, default=4096, help="the most walks per point")
parser.add_argument("--smoothing", type=float, default=2.0, help="Gaussian width (mm)")
parser.add_argument("--tolerance", type=float, default=1e-8, help="the grid's relative residual")
parser.add_argument("--seed", type=int, default=1)
args = parser.parse_args()

p = bioheat_tissues.head_inputs()
ct_array, inside_slice, skin, tissues = p["ct_array"], p["inside"], p["skin_u"], p["tissues"]
image = servermanager.Fetch(tissues)
nx, ny, nz = image.GetDimensions()
hx, hy, hz = image.GetSpacing()


def grid_array(name):
    return vtk_to_numpy(image.GetPointData().GetArray(name)).astype(float).reshape(nz, ny, nx)


k = grid_array("Conductivity")
sigma = grid_array("Perfusion")
f = grid_array("Heat")
inside = grid_array(ct_array) >= ct_workflow.SKIN_ISO_VALUE
boundary_u = bioheat_tissues.SKIN_TEMPERATURE - bioheat_tissues.ARTERIAL_TEMPERATURE

# −∇·(k∇u) + σu = −f on the inside voxels, u = boundary_u on the others:
# face coefficients k_face/h² per axis (harmonic means), the known values
# moved to the right-hand side.
start = time.perf_counter()
faces = []
for axis, h in ((2, hx), (1, hy), (0, hz)):
    a = [slice(None)] * 3
    b = [slice(None)] * 3
    a[axis] = slice(None, -1)
    b[axis] = slice(1, None)
    ka, kb = k[tuple(a)], k[tuple(b)]
    faces.append((axis, tuple(a), tuple(b), 2.0 * ka * kb / (ka + kb) / (h * h)))
diagonal = np.where(inside, sigma, 1.0)
rhs = np.where(inside, -f, boundary_u)
for axis, a, b, c in faces:
    # Each face adds c to both its voxels' diagonals (inside ones) and, where
    # the other voxel is a boundary voxel, c·u_b to the right-hand side.
    diagonal[a] += np.where(inside[a], c, 0.0)
    diagonal[b] += np.where(inside[b], c, 0.0)
    rhs[a] += np.where(inside[a] & ~inside[b], c * boundary_u, 0.0)
    rhs[b] += np.where(inside[b] & ~inside[a], c * boundary_u, 0.0)


def apply(u):
    """The operator on the inside voxels (the identity on the others)."""
    out = diagonal * u
    for axis, a, b, c in faces:
        both = inside[a] & inside[b]
        out[a] -= np.where(both, c * u[b], 0.0)
        out[b] -= np.where(both, c * u[a], 0.0)
    return out


u = np.full(k.shape, boundary_u)
r = rhs - apply(u)
z = r / diagonal
d = z.copy()
rz = float(np.vdot(r, z))
norm_rhs = float(np.linalg.norm(rhs))
iterations = 0
while float(np.linalg.norm(r)) > args.tolerance * norm_rhs and iterations < 100000:
    q = apply(d)
    step = rz / float(np.vdot(d, q))
    u += step * d
    r -= step * q
    z = r / diagonal
    rz_next = float(np.vdot(r, z))
    d = z + (rz_next / rz) * d
    rz = rz_next
    iterations += 1
grid_seconds = time.perf_counter() - start
unknowns = int(inside.sum())

# The walk on the slice's points inside the head.
walk = bioheat_tissues.bioheat_solver(skin, inside_slice, tissues, walks=args.most,
                                      target=args.target, smoothing=args.smoothing,
                                      seed=args.seed)
# Wall time, as the grid's: the boundary's hierarchy, the coefficients'
# smoothing and bounds, and the walks.
start = time.perf_counter()
walk.UpdatePipeline()
walk_seconds = time.perf_counter() - start
walks = walk.FieldData["TotalWalks"].GetRange()[0]

# The grid's solution onto the slice (trilinear), beside the walk's.
solved = pvs.PassArrays(Input=tissues, PointDataArrays=[])
solved.UpdatePipeline()
grid_image = servermanager.Fetch(solved)
values = numpy_to_vtk(u.ravel().copy(), deep=1)
values.SetName("U_Grid")
grid_image.GetPointData().AddArray(values)
producer = pvs.TrivialProducer()
producer.GetClientSideObject().SetOutput(grid_image)
probed = pvs.ResampleWithDataset(SourceDataArrays=producer, DestinationMesh=walk)
probed.PassPointArrays = 1
data = servermanager.Fetch(probed)
walk_u = vtk_to_numpy(data.GetPointData().GetArray("U"))
walk_se = np.sqrt(vtk_to_numpy(data.GetPointData().GetArray("U_Variance")))
grid_u = vtk_to_numpy(data.GetPointData().GetArray("U_Grid"))
mask = data.GetPointData().GetArray("vtkValidPointMask")
valid = vtk_to_numpy(mask).astype(bool) if mask else np.ones(walk_u.shape, dtype=bool)
difference = (walk_u - grid_u)[valid]

print("| solve | unknowns or points | seconds | iterations or walks | "
      "standard error RMS / largest (°C) |")
print("|---|---:|---:|---:|---:|")
print("| grid: whole head at the CT's resolution, NumPy PCG | %d | %.2f | %d | — |"
      % (unknowns, grid_seconds, iterations))
how = ("to %.2g °C (at least %d walks per point)" % (args.target, builtins.min(128, args.most))
       if args.target > 0 else "%d walks per point" % args.most)
print("| walk: slice inside the head, %s | %d | %.2f | %.3g | %.3f / %.3f |"
      % (how, len(walk_u), walk_seconds, walks,
         math.sqrt(float(np.mean(walk_se ** 2))), float(np.max(walk_se))))
print("\nwalk minus grid on the slice (%d points): mean %+.3f °C, RMS %.3f °C, largest |.| %.3f °C"
      % (difference.size, float(np.mean(difference)), math.sqrt(float(np.mean(difference ** 2))),
         float(np.max(np.abs(difference))) if difference.size else 0.0))
sys.stdout.flush()
