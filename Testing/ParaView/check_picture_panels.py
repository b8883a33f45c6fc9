"""Checks that a picture made by an example is not blank: split into a grid
of panels, every panel must show many colours (a rendered, colour-mapped
view has hundreds; an empty or single-colour one a handful).

    check_picture_panels.py PICTURE.png ROWS COLUMNS [MIN_COLOURS]
"""
import sys

from vtkmodules.vtkIOImage import vtkPNGReader


def main():
    path, rows, columns = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    minimum = int(sys.argv[4]) if len(sys.argv) > 4 else 100
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    image = png.GetOutput()
    width, height, _ = image.GetDimensions()
    assert width >= 400 and height >= 400, (path, width, height)
    pixels = image.GetPointData().GetScalars()
    for r in range(rows):
        for c in range(columns):
            colours = set()
            for row in range(r * height // rows, (r + 1) * height // rows, 3):
                for col in range(c * width // columns, (c + 1) * width // columns, 3):
                    colours.add(pixels.GetTuple(row * width + col)[:3])
            assert len(colours) > minimum, (path, "panel", r, c, len(colours))
    print(f"ok: {path}: {rows * columns} panels rendered")


if __name__ == "__main__":
    main()
