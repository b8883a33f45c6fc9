"""The tissue table of the bioheat examples: thermal conductivity k, blood
perfusion w (the volumetric perfusion rate times the blood's density and heat
capacity) and metabolic heat Q per tissue class of the headsq CT, and a
ParaView filter that turns the CT values into the arrays the Walk On Spheres
Solver's Varying Coefficients take.

Sources:
- skin, muscle, brain (undifferentiated) and blood: IT'IS Foundation tissue
  properties database V4.2 (itis.swiss/virtual-population/tissue-properties,
  doi:10.13099/VIP21000-04-2): conductivity (W/(m K)), heat transfer rate
  (ml/(min kg)), density (kg/m³) and heat generation rate (W/kg):
  skin 0.372, 106.4, 1109; muscle 0.495, 36.74, 1090.4; brain 0.513, 558.6,
  1045.5, 11.37 W/kg; blood density 1049.75 kg/m³ and heat capacity
  3617 J/(kg K). w = rate·1e-6/60 · density · 1049.75 · 3617, so skin
  7,466, muscle 2,535 and brain 36,958 W/(m³ K); the brain's Q is
  11,884 W/m³;
- fat: the same database's subcutaneous fat ("SAT"): 0.211 W/(m K),
  32.71 ml/(min kg), 911 kg/m³ and 0.507 W/kg, so w = 1,886 W/(m³ K) and
  Q = 461 W/m³;
- skull bone: Table 1 of Cancers 11(8):1183, 2019
  (doi:10.3390/cancers11081183; thermal values from the IT'IS database):
  k = 0.40 W/(m K), w = 3400 W/(m³ K).
The metabolic heat of skin, muscle and bone was not in the sources read and
is taken as 0; the brain's dominates the head's heat in any case.

Classes from the CT values v of headsq, read as Hounsfield units v − 1024
(air is about 0 in the file and the soft tissue peak lies at about 1060,
+36 HU): outside the head below the skin's iso-value 500 (the boundary of
ct_workflow.py; air around the head and in its cavities), skin from 500 to
834 (−524 to −190 HU: the partial-volume rim where the skin meets the air),
fat from 834 to 994 (−190 to −30 HU), soft tissue from 994 to 1174 (−30 to
+150 HU) and bone above. Soft tissue is brain where it lies deeper than
10 mm inside the head (the head mask v > 500 eroded by 10 mm), muscle
elsewhere. At 3.2 × 3.2 × 1.5 mm these classes are approximate: the depth
rule puts deep soft tissue of the face and neck in the brain class, and the
skin, 1 to 2 mm thick, is only seen through the rim's partial volume.

Outside the head the equation is not solved, but the smoothing of the
coefficients reaches a few millimetres into it: the voxels outside take the
skin's coefficients, so that no layer of air's conductivity (0.026 W/(m K),
twenty times below the tissues') is smeared along the inside of the skin.
Such a layer is not in the body, and its steep coefficients made the walks
several times slower.

Units: the head is in millimetres. Dividing the equation by 1e6 keeps k in
W/(m K) and scales w and Q by 1e-6 (coefficients_per_mm).
"""
import os

import paraview.simple as pvs

import ct_workflow

ARTERIAL_TEMPERATURE = 37.0  # °C, T_a
SKIN_TEMPERATURE = 34.0      # °C, the skin held by a room-facing boundary

BLOOD_DENSITY = 1049.75      # kg/m³ (IT'IS v4.2)
BLOOD_HEAT_CAPACITY = 3617.0  # J/(kg K) (IT'IS v4.2)


def perfusion_of(ml_per_min_per_kg, density):
    """w in W/(m³ K) from a heat transfer rate in ml/(min kg)."""
    return ml_per_min_per_kg * 1e-6 / 60.0 * density * BLOOD_DENSITY * BLOOD_HEAT_CAPACITY


# name: (k W/(m K), w W/(m³ K), Q W/m³), in the order of the Tissue codes.
# Code 0 is the outside of the head, which takes the skin's coefficients.
TISSUES = {
    "outside (air)": None,
    "skin": (0.372, perfusion_of(106.4, 1109.0), 0.0),
    "fat": (0.211, perfusion_of(32.71, 911.0), 0.507 * 911.0),
    "muscle": (0.495, perfusion_of(36.74, 1090.4), 0.0),
    "brain": (0.513, perfusion_of(558.6, 1045.5), 11.37 * 1045.5),
    "bone": (0.40, 3400.0, 0.0),
}

# CT value bounds of the classes (Hounsfield units + 1024), and the depth of
# the brain class.
OUTSIDE_BELOW = 500.0  # the skin iso-value of ct_workflow.py
FAT_ABOVE = 834.0      # −190 HU
SOFT_ABOVE = 994.0     # −30 HU
BONE_ABOVE = 1174.0    # +150 HU
BRAIN_DEPTH = 10.0     # mm


def coefficients_per_mm(tissue):
    """α, σ, f of ∇·(α∇u) − σu = f for u = T − T_a with lengths in mm:
    α = k, σ = w·1e-6, f = −Q·1e-6."""
    k, w, q = tissue
    return k, w * 1e-6, -q * 1e-6


def tissue_table():
    """(k, w, Q) per Tissue code, the outside taking the skin's."""
    return [TISSUES["skin"] if values is None else values for values in TISSUES.values()]


def tissue_arrays(volume, ct_array):
    """A Programmable Filter on the CT volume that adds the point arrays
    Tissue (0 outside, 1 skin, 2 fat, 3 muscle, 4 brain, 5 bone),
    Conductivity (α), Perfusion (σ) and Heat (f) of coefficients_per_mm."""
    table = [coefficients_per_mm(values) for values in tissue_table()]
    script = """
import numpy as np
image = inputs[0]
nx, ny, nz = image.GetDimensions()
sx, sy, sz = image.GetSpacing()
v = np.asarray(image.PointData[%(array)r], dtype=float).reshape(nz, ny, nx)
# The head eroded by the brain's depth, axis by axis (anisotropic voxels).
deep = v > %(outside)r
for axis, spacing in ((2, sx), (1, sy), (0, sz)):
    for _ in range(int(round(%(depth)r / spacing))):
        shrunk = deep.copy()
        front = [slice(None)] * 3
        back = [slice(None)] * 3
        front[axis] = slice(1, None)
        back[axis] = slice(None, -1)
        shrunk[tuple(back)] &= deep[tuple(front)]
        shrunk[tuple(front)] &= deep[tuple(back)]
        edge = [slice(None)] * 3
        edge[axis] = 0
        shrunk[tuple(edge)] = False
        edge[axis] = -1
        shrunk[tuple(edge)] = False
        deep = shrunk
tissue = np.full(v.shape, 1, dtype=np.int32)
tissue[v >= %(fat)r] = 2
soft = (v >= %(soft)r) & (v <= %(bone)r)
tissue[soft] = 3
tissue[soft & deep] = 4
tissue[v > %(bone)r] = 5
tissue[v < %(outside)r] = 0
tissue = tissue.ravel()
table = np.array(%(table)r)
for k, label in enumerate(("Conductivity", "Perfusion", "Heat")):
    output.PointData.append(table[tissue, k], label)
output.PointData.append(tissue, "Tissue")
""" % {"array": ct_array, "outside": OUTSIDE_BELOW, "fat": FAT_ABOVE, "soft": SOFT_ABOVE,
       "bone": BONE_ABOVE, "depth": BRAIN_DEPTH, "table": table}
    f = pvs.ProgrammableFilter(Input=volume)
    f.Script = script
    f.CopyArrays = 1
    pvs.RenameSource("Tissue coefficients", f)
    return f


def bioheat_solver(boundary, probe, tissues, constant=False, walks=512, target=0.05,
                   smoothing=2.0, seed=0, constant_tissue="brain"):
    """A Walk On Spheres Solver of the steady Pennes equation for u = T − T_a
    on `probe`, the skin (`boundary`, with u in its point array U) held, and
    the gradient on: with `tissues` (tissue_arrays) as Varying Coefficients,
    or, with constant=True, one tissue's k, w and Q everywhere (the brain's
    unless `constant_tissue` names another) as the screened Poisson equation
    (Δu − (w/k)u = −Q/k)."""
    s = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
    s.BoundaryValues = ["POINTS", "U"]
    s.ComputeGradient = 1
    s.WalksPerPoint = walks
    s.TargetStandardError = target
    s.KeepRunningSums = 0
    s.Seed = seed
    if constant:
        alpha, sigma, f = coefficients_per_mm(TISSUES[constant_tissue])
        s.Equation = "Screened Poisson"
        s.ScreeningCoefficient = sigma / alpha
        s.SourceExpression = "%.10g" % (f / alpha)
    else:
        s.Source = tissues
        s.Equation = "Varying Coefficients"
        s.DiffusionFromArray = 1
        s.DiffusionCoefficientArray = ["POINTS", "Conductivity"]
        s.AbsorptionFromArray = 1
        s.AbsorptionCoefficientArray = ["POINTS", "Perfusion"]
        s.SourceTermFromArray = 1
        s.SourceArray = ["POINTS", "Heat"]
        s.CoefficientSmoothing = smoothing
    return s


def head_inputs(volume=None, slice_z=70.0):
    """The CT workflow's pipeline (ct_workflow.build_pipeline; its own
    Poisson solver is deleted) with what the bioheat solvers take: `skin`
    (the skin with u = T − T_a = −3 °C in its array U), `inside` (the slice's
    points inside the head, where the equation holds) and `tissues`
    (tissue_arrays of the padded volume); `ct_array` names the CT values."""
    volume = volume or os.path.join(ct_workflow.data_folder(), ct_workflow.VOLUME_NAME)
    p = ct_workflow.build_pipeline(volume, walks=1, slice_z=slice_z, polynomial=0)
    pvs.Delete(p["solver"])
    p["ct_array"] = p["volume"].PointData.keys()[0]
    p["inside"] = pvs.Threshold(Input=p["slice"], Scalars=["POINTS", p["ct_array"]],
                                LowerThreshold=ct_workflow.SKIN_ISO_VALUE,
                                UpperThreshold=1e9, AllScalars=1)
    pvs.RenameSource("Slice inside the head", p["inside"])
    p["skin_u"] = pvs.Calculator(Input=p["skin"], ResultArrayName="U",
                                 Function="%g" % (SKIN_TEMPERATURE - ARTERIAL_TEMPERATURE))
    pvs.RenameSource("Skin at 34 °C (u = T - T_a)", p["skin_u"])
    p["tissues"] = tissue_arrays(p["padded"], p["ct_array"])
    for name in ("inside", "skin_u", "tissues"):
        p[name].UpdatePipeline()
    return p
