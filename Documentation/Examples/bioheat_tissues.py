"""The tissue table of the bioheat examples: thermal conductivity k, blood
perfusion w (the volumetric perfusion rate times the blood's density and heat
capacity) and metabolic heat Q per tissue class of the headsq CT, and a
ParaView filter that turns the CT values into the arrays the Walk On Spheres
Solver's Varying Coefficients take.

Sources:
- brain (undifferentiated): IT'IS Foundation tissue properties database
  v4.2 (itis.swiss/virtual-population/tissue-properties): k = 0.513 W/(m K),
  density 1045.5 kg/m³, heat transfer rate 558.6 ml/(min kg), heat
  generation rate 11.37 W/kg; blood density 1049.75 kg/m³ and heat capacity
  3617 J/(kg K) (the same database), so w = 558.6e-6/60 · 1045.5 · 1049.75 ·
  3617 ≈ 3.70e4 W/(m³ K) and Q ≈ 1.19e4 W/m³;
- skull bone, skin and other soft tissue, air: Table 1 of Cancers
  11(8):1183, 2019 (doi:10.3390/cancers11081183; thermal values from the
  IT'IS database, its muscle perfusion raised for hyperthermia and not used
  here): bone k = 0.40,
  w = 3400; skin k = 0.42, w = 8065; air k = 0.024, w = 0 (W/(m K) and
  W/(m³ K)). Their metabolic heat is not tabulated there and is taken as 0.

Classes from the CT values v of headsq (which is not calibrated to
Hounsfield units: air about 0, soft tissue inside the head about 1050 to
1150, bone above 1150) and from depth: air below 624, bone above 1174 (the
bone surface of the test data is the iso 1150), skin and fat from 624 to
1000 (the partial-volume rim and fat), and soft tissue above 1000: brain
where it lies deeper than 10 mm inside the head (the head mask v > 500
eroded by 10 mm), muscle and scalp elsewhere (muscle from the same table:
k = 0.56, w = 12,960/4 = 3240, its resting perfusion). At 3.2 × 3.2 × 1.5 mm
these classes are approximate: the depth rule puts deep soft tissue of the
face and neck in the brain class.

Units: the head is in millimetres. Dividing the equation by 1e6 keeps k in
W/(m K) and scales w and Q by 1e-6 (coefficients_per_mm).
"""
import paraview.simple as pvs

ARTERIAL_TEMPERATURE = 37.0  # °C, T_a
SKIN_TEMPERATURE = 34.0      # °C, the skin held by a room-facing boundary

BLOOD_DENSITY = 1049.75      # kg/m³ (IT'IS v4.2)
BLOOD_HEAT_CAPACITY = 3617.0  # J/(kg K) (IT'IS v4.2)


def perfusion_of(ml_per_min_per_kg, density):
    """w in W/(m³ K) from a heat transfer rate in ml/(min kg)."""
    return ml_per_min_per_kg * 1e-6 / 60.0 * density * BLOOD_DENSITY * BLOOD_HEAT_CAPACITY


# name: (k W/(m K), w W/(m³ K), Q W/m³), in the order of the Tissue codes.
TISSUES = {
    "air": (0.024, 0.0, 0.0),
    "skin and fat": (0.42, 8065.0, 0.0),
    "muscle": (0.56, 3240.0, 0.0),
    "brain": (0.513, perfusion_of(558.6, 1045.5), 11.37 * 1045.5),
    "bone": (0.40, 3400.0, 0.0),
}

# CT value bounds of the classes, and the depth of the brain class.
AIR_BELOW = 624.0
SOFT_ABOVE = 1000.0
BONE_ABOVE = 1174.0
HEAD_ABOVE = 500.0
BRAIN_DEPTH = 10.0  # mm


def coefficients_per_mm(tissue):
    """α, σ, f of ∇·(α∇u) − σu = f for u = T − T_a with lengths in mm:
    α = k, σ = w·1e-6, f = −Q·1e-6."""
    k, w, q = tissue
    return k, w * 1e-6, -q * 1e-6


def tissue_arrays(volume, ct_array):
    """A Programmable Filter on the CT volume that adds the point arrays
    Tissue (0 air, 1 skin and fat, 2 muscle, 3 brain, 4 bone),
    Conductivity (α), Perfusion (σ) and Heat (f) of coefficients_per_mm."""
    table = [coefficients_per_mm(values) for values in TISSUES.values()]
    script = """
import numpy as np
image = inputs[0]
nx, ny, nz = image.GetDimensions()
sx, sy, sz = image.GetSpacing()
v = np.asarray(image.PointData[%(array)r], dtype=float).reshape(nz, ny, nx)
# The head eroded by the brain's depth, axis by axis (anisotropic voxels).
deep = v > %(head)r
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
tissue[v < %(air)r] = 0
soft = (v > %(soft)r) & (v <= %(bone)r)
tissue[soft] = 2
tissue[soft & deep] = 3
tissue[v > %(bone)r] = 4
tissue = tissue.ravel()
table = np.array(%(table)r)
for k, label in enumerate(("Conductivity", "Perfusion", "Heat")):
    output.PointData.append(table[tissue, k], label)
output.PointData.append(tissue, "Tissue")
""" % {"array": ct_array, "air": AIR_BELOW, "soft": SOFT_ABOVE, "bone": BONE_ABOVE,
       "head": HEAD_ABOVE, "depth": BRAIN_DEPTH, "table": table}
    f = pvs.ProgrammableFilter(Input=volume)
    f.Script = script
    f.CopyArrays = 1
    pvs.RenameSource("Tissue coefficients", f)
    return f
