"""Denoising (paper Sec. 5.2.4): vtkWalkOnSpheresDenoiser averages each
estimate with its neighbours, guided by the variance and by the boundary
value at the closest boundary point. For T = x² − y² on the unit sphere the
solution inside is x² − y² itself, so the error is known at every point."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import MessageCatcher, saddle, sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
BOUNDARY = sphere_boundary()


def slice_through_the_ball():
    """64 x 64 points on the square [-0.6, 0.6]² at z = 0, inside the ball."""
    source = vtkPlaneSource()
    source.SetOrigin(-0.6, -0.6, 0.0)
    source.SetPoint1(0.6, -0.6, 0.0)
    source.SetPoint2(-0.6, 0.6, 0.0)
    source.SetResolution(63, 63)
    source.Update()
    return source.GetOutput()


def solve(probe, walks=16):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(BOUNDARY)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.Update()
    return solver.GetOutput()


PROBE = slice_through_the_ball()
NOISY = solve(PROBE)


def denoise(data, **settings):
    denoiser = gridfree.vtkWalkOnSpheresDenoiser()
    catcher = MessageCatcher(denoiser, denoiser.GetExecutive())
    denoiser.SetInputData(data)
    for name, value in settings.items():
        getattr(denoiser, "Set" + name)(value)
    denoiser.Update()
    return denoiser, catcher


def tuples(data, name):
    array = data.GetPointData().GetArray(name)
    return [array.GetTuple(i) for i in range(array.GetNumberOfTuples())]


def rmse(data, name):
    values = data.GetPointData().GetArray(name)
    n = data.GetNumberOfPoints()
    return math.sqrt(sum((values.GetTuple1(i) - saddle(*data.GetPoint(i))) ** 2
                         for i in range(n)) / n)


def copy_without(data, name):
    copy = vtkPolyData()
    copy.DeepCopy(data)
    copy.GetPointData().RemoveArray(name)
    return copy


def test_denoising_at_least_halves_the_error_of_16_walks():
    # The range term compares single estimates, each as noisy as 16 walks
    # make it; with k = 2 (the default) it averages what that noise
    # explains. The guide (T_ClosestBoundaryValue, found by its default
    # name) stays on.
    denoiser, catcher = denoise(NOISY)
    assert catcher.errors == [] and catcher.warnings == []
    out = denoiser.GetOutput()
    assert out.IsA("vtkPolyData")
    assert out.GetNumberOfPoints() == PROBE.GetNumberOfPoints()
    assert out.GetNumberOfPolys() == PROBE.GetNumberOfPolys()
    assert denoiser.GetLastGuideSigma() > 0.0
    assert rmse(out, "T") <= 0.5 * rmse(NOISY, "T")

    # The noisy estimates are kept; T is still the active scalars; the
    # solver's other arrays pass through.
    pd = out.GetPointData()
    assert tuples(out, "T_Noisy") == tuples(NOISY, "T")
    assert tuples(out, "T_Noisy_Variance") == tuples(NOISY, "T_Variance")
    assert pd.GetScalars().GetName() == "T"
    for name in ("WalkSteps", "BoundaryDistance", "T_ClosestBoundaryValue"):
        assert tuples(out, name) == tuples(NOISY, name)
    # The propagated variance: the noise left is smaller than the input's.
    before = sum(v for (v,) in tuples(NOISY, "T_Variance"))
    after = sum(v for (v,) in tuples(out, "T_Variance"))
    assert after < 0.25 * before
    assert out.GetFieldData().GetArray("DenoiseSeconds").GetNumberOfTuples() == 1


def test_a_stricter_range_term_still_lowers_the_error():
    denoiser, catcher = denoise(NOISY, VarianceScale=1.0)
    assert catcher.errors == []
    assert rmse(denoiser.GetOutput(), "T") <= rmse(NOISY, "T") / 1.5


def test_an_image_stays_an_image():
    image = vtkImageData()
    image.SetDimensions(12, 10, 1)
    image.SetOrigin(-0.5, -0.4, 0.1)
    image.SetSpacing(0.09, 0.09, 1.0)
    denoiser, catcher = denoise(solve(image, walks=8))
    assert catcher.errors == []
    out = denoiser.GetOutput()
    assert out.IsA("vtkImageData")
    assert out.GetDimensions() == (12, 10, 1)
    # Relative to the spacing: 2 spacings by default.
    assert abs(denoiser.GetLastSpatialSigma() - 2 * 0.09) < 1e-9


def test_missing_variance_is_an_error_and_the_input_passes_through():
    data = copy_without(NOISY, "T_Variance")
    denoiser, catcher = denoise(data)
    assert "No variance for 'T'" in catcher.error_text()
    assert "T_Variance" in catcher.error_text()
    out = denoiser.GetOutput()
    assert out.GetNumberOfPoints() == data.GetNumberOfPoints()
    assert out.GetPointData().GetArray("T_Noisy") is None
    assert tuples(out, "T") == tuples(data, "T")


def test_missing_or_unusable_value_arrays_are_errors():
    denoiser = gridfree.vtkWalkOnSpheresDenoiser()
    catcher = MessageCatcher(denoiser, denoiser.GetExecutive())
    denoiser.SetInputData(NOISY)
    denoiser.SetInputArrayToProcess(0, 0, 0, POINTS, "Missing")
    denoiser.Update()
    assert "no point array named 'Missing'" in catcher.error_text()

    # A variance array with the wrong number of components.
    denoiser = gridfree.vtkWalkOnSpheresDenoiser()
    catcher = MessageCatcher(denoiser, denoiser.GetExecutive())
    denoiser.SetInputData(NOISY)
    denoiser.SetInputArrayToProcess(1, 0, 0, POINTS, "Normals")
    denoiser.Update()
    assert "3 components" in catcher.error_text()


def test_missing_guide_is_a_warning_unless_the_guide_is_off():
    data = copy_without(NOISY, "T_ClosestBoundaryValue")
    denoiser, catcher = denoise(data)
    assert catcher.errors == []
    assert "without a guide" in catcher.warning_text()
    assert denoiser.GetLastGuideSigma() == 0.0
    assert denoiser.GetOutput().GetPointData().GetArray("T_Noisy") is not None

    denoiser, catcher = denoise(data, UseGuide=False)
    assert catcher.errors == [] and catcher.warnings == []


def test_one_and_two_threads_give_the_same_output():
    one, _ = denoise(NOISY, NumberOfThreads=1)
    two, _ = denoise(NOISY, NumberOfThreads=2)
    for name in ("T", "T_Variance"):
        assert tuples(one.GetOutput(), name) == tuples(two.GetOutput(), name)
