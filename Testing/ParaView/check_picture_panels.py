"""Checks that a picture made by an example is not blank: split into a grid
of panels, the middle of every panel (where the data are drawn; titles sit
at the top) must differ from the panel's background in a good share of its
pixels. The background is the most common colour of the panel's border.

    check_picture_panels.py PICTURE.png ROWS COLUMNS [MIN_COVERED_FRACTION]
"""
import collections
import sys

from vtkmodules.vtkIOImage import vtkPNGReader


def main():
    path, rows, columns = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    minimum = float(sys.argv[4]) if len(sys.argv) > 4 else 0.1
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    image = png.GetOutput()
    width, height, _ = image.GetDimensions()
    assert width >= 400 and height >= 400, (path, width, height)
    pixels = image.GetPointData().GetScalars()

    def colour(col, row):
        return pixels.GetTuple(row * width + col)[:3]

    for r in range(rows):
        for c in range(columns):
            x0, x1 = c * width // columns, (c + 1) * width // columns
            y0, y1 = r * height // rows, (r + 1) * height // rows
            border = [colour(x, y) for x in range(x0 + 2, x1 - 2, 3) for y in (y0 + 2, y1 - 3)]
            border += [colour(x, y) for y in range(y0 + 2, y1 - 2, 3) for x in (x0 + 2, x1 - 3)]
            background = collections.Counter(border).most_common(1)[0][0]
            middle = [colour(x, y) for x in range((3 * x0 + x1) // 4, (x0 + 3 * x1) // 4, 2)
                      for y in range((3 * y0 + y1) // 4, (y0 + 3 * y1) // 4, 2)]
            covered = sum(1 for p in middle if max(abs(a - b) for a, b in zip(p, background)) > 24)
            fraction = covered / len(middle)
            assert fraction > minimum, (path, "panel", r, c, fraction)
    print(f"ok: {path}: {rows * columns} panels rendered")


if __name__ == "__main__":
    main()
