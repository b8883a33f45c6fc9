"""The plain-VTK example Documentation/Examples/ct_gradient_streamlines.py,
run small: it must finish, report its run and write a picture that is not
blank. Rendering needs a display (ctest runs this under xvfb-run)."""
import os
import re
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.normpath(os.path.join(HERE, "..", ".."))
EXAMPLE = os.path.join(SOURCE, "Documentation", "Examples", "ct_gradient_streamlines.py")
DATA = os.environ.get("GRIDFREE_DATA", os.path.join(SOURCE, "Data"))


def read_png(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[:, :, :3]


def test_example_renders_a_picture(tmp_path):
    folder = os.environ.get("GRIDFREE_EXAMPLE_OUTPUT", str(tmp_path))
    output = os.path.join(folder, "ct_gradient_streamlines.png")
    if os.path.exists(output):
        os.remove(output)
    run = subprocess.run(
        [sys.executable, EXAMPLE,
         "--data", os.path.join(DATA, "headsq_skin_iso500_closed.vtp"),
         "--output", output, "--walks", "16", "--resolution", "40", "--size", "1000", "750"],
        capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    for word in ("points: 1600", "(16 per point, more at", "seconds:", "streamlines:"):
        assert word in run.stdout, (word, run.stdout)
    # 16 walks at each point, and more at the points that walked on for a
    # reliable error bar (at most 4 times as many).
    walks = int(re.search(r"walks: (\d+) ", run.stdout).group(1))
    walked_on = int(re.search(r"more at (\d+) points", run.stdout).group(1))
    assert 1600 * 16 + walked_on * 16 <= walks <= 1600 * 16 + walked_on * 48, run.stdout
    assert os.path.isfile(output)

    pixels = read_png(output)
    height, width, _ = pixels.shape
    assert (width, height) == (1000, 750), (width, height)
    # As in the demo's check: a blank or single-colour picture has a handful
    # of colours; a rendered colour-mapped slice with glyphs has hundreds.
    sample = pixels[::4, ::4].reshape(-1, 3)
    colors = {tuple(p) for p in sample}
    assert len(colors) > 100, len(colors)
    # Not all background (white): the slice fills a good part of the picture.
    background = np.all(sample == 255, axis=1).mean()
    assert background < 0.8, background
    # The main view (left of the colour bars) shows the slice's dark and warm colours.
    view = pixels[:, : int(0.8 * width)].reshape(-1, 3).astype(int)
    warm = ((view[:, 0] > 180) & (view[:, 2] < 120)).mean()
    assert warm > 0.02, warm
