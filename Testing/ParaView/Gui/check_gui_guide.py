"""Checks the solve saved by user_guide_steps.xml, the user guide's CT
workflow built by clicks: the Slice of the padded volume at z = 70 (4,096
points, as the script's), the temperature with its variance and gradient
at every point, heated by the CT source above the boundary's values inside
the head (the Poisson source was connected and its sign is right), the
gradient finite.

    python3 check_gui_guide.py guide_slice.vtp"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
out = reader.GetOutput()
pd = out.GetPointData()
n = out.GetNumberOfPoints()
assert n == 4096, n
z = {round(out.GetPoint(i)[2], 6) for i in range(n)}
assert z == {70.0}, z
T, ct, grad = pd.GetArray("T"), pd.GetArray("MetaImage"), pd.GetArray("T_Gradient")
assert T is not None and pd.GetArray("T_Variance") is not None and grad is not None
assert all(math.isfinite(grad.GetValue(k)) for k in range(grad.GetNumberOfValues()))
inside = [T.GetValue(i) for i in range(n) if ct.GetValue(i) >= 500]
assert len(inside) > 1000, len(inside)
# The boundary's T on the skin stays within about 12..45; the CT heating
# raises the middle of the head well above the mean of its boundary values.
assert max(inside) > 40.0 and min(inside) > 10.0, (min(inside), max(inside))
print("ok: the guide's workflow by clicks solved the slice (%d points, %d inside the head, "
      "T %.1f to %.1f inside)" % (n, len(inside), min(inside), max(inside)))
