"""Checks what mark_conditions.xml saved: the marked surface has bc = 1
(Neumann) on exactly the cells whose centre lies above z = 0.7 and 0
elsewhere, with MarkedCells counting them; and the solve on it is a
walk-on-stars solve within the maximum principle's bounds (check_gui_mixed.py).

    python3 check_gui_marked.py gui_marked.vtp gui_mixed.vtp"""
import os
import subprocess
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
surface = reader.GetOutput()
bc = surface.GetCellData().GetArray("bc")
assert bc is not None, "no bc cell array"
marked = 0
for cell in range(surface.GetNumberOfCells()):
    ids = surface.GetCell(cell).GetPointIds()
    z = sum(surface.GetPoint(ids.GetId(k))[2] for k in range(ids.GetNumberOfIds())) \
        / ids.GetNumberOfIds()
    want = 1 if z > 0.7 else 0
    assert bc.GetValue(cell) == want, (cell, z, bc.GetValue(cell))
    marked += want
assert marked > 0
assert surface.GetFieldData().GetArray("MarkedCells").GetValue(0) == marked
print("ok: %d cells above z = 0.7 marked Neumann by clicks" % marked)
subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "check_gui_mixed.py"),
                sys.argv[2]], check=True)
