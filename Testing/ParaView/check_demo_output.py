"""Checks the demo's output: the slice file has the solution arrays and the
PNG shows two non-blank panels (solution and variance)."""
import os
import sys

from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

folder = sys.argv[1]

reader = vtkXMLPolyDataReader()
reader.SetFileName(os.path.join(folder, "head_slice.vtp"))
reader.Update()
slice_data = reader.GetOutput()
assert slice_data.GetNumberOfPoints() == 3600, slice_data.GetNumberOfPoints()
for name in ("T", "T_Variance", "WalkSteps", "EscapedFraction"):
    assert slice_data.GetPointData().GetArray(name) is not None, name
low, high = slice_data.GetPointData().GetArray("T").GetRange()
assert high > low, (low, high)

png = vtkPNGReader()
png.SetFileName(os.path.join(folder, "head_slice.png"))
png.Update()
image = png.GetOutput()
width, height, _ = image.GetDimensions()
assert width >= 1000 and height >= 400, (width, height)
pixels = image.GetPointData().GetScalars()
components = pixels.GetNumberOfComponents()
for half in (0, 1):
    colors = set()
    for row in range(0, height, 4):
        for col in range(half * width // 2, (half + 1) * width // 2, 4):
            colors.add(pixels.GetTuple(row * width + col)[:3])
    # A blank or single-colour panel has a handful of colours; a rendered
    # colour-mapped slice has hundreds.
    assert len(colors) > 100, ("panel", half, len(colors))
print("ok: slice arrays and both panels rendered")
