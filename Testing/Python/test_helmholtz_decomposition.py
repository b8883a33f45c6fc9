"""Helmholtz-Hodge decomposition (paper Sec. 6.6) of fields built from known
potentials: on a cube (3D) and a square (2D), X = grad(u0) + curl(A0) +
grad(h) with u0 and A0 zero on the boundary (A0 divergence-free) and h
harmonic, so the decomposition's parts are exactly grad(u0), curl(A0) and
grad(h). Every part is checked within 5 standard errors at every point, the
reported variances against the observed spread (mean z^2), the sum of the
parts against X, an image field against the same field as an expression, the
thread-count independence, and the errors for bad input."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkCubeSource  # noqa: E402

from gridfree_testing import MessageCatcher, closed_polyline, point_cloud  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS

# 3D, on the cube [-1, 1]^3, with b = (1-x^2)(1-y^2)(1-z^2):
# u0 = b (1 + x + 2y); A0 = (dw/dy, -dw/dx, 0), w = b^2 (zero on the faces,
# divergence-free); h = x^2 - y^2 + 2xz. The three parts, as expressions
# (ExprTk syntax) and as Python functions.
CURL_FREE_3D = (
    "-(y - 1)*(y + 1)*(z - 1)*(z + 1)*(3*pow(x, 2) + 4*x*y + 2*x - 1)",
    "-2*(x - 1)*(x + 1)*(z - 1)*(z + 1)*(x*y + 3*pow(y, 2) + y - 1)",
    "-2*z*(x - 1)*(x + 1)*(y - 1)*(y + 1)*(x + 2*y + 1)")
DIVERGENCE_FREE_3D = (
    "16*x*z*(x - 1)*(x + 1)*pow(y - 1, 2)*pow(y + 1, 2)*(z - 1)*(z + 1)",
    "16*y*z*pow(x - 1, 2)*pow(x + 1, 2)*(y - 1)*(y + 1)*(z - 1)*(z + 1)",
    "-4*pow(z - 1, 2)*pow(z + 1, 2)*(3*pow(x, 4)*pow(y, 2) - pow(x, 4) + "
    "3*pow(x, 2)*pow(y, 4) - 12*pow(x, 2)*pow(y, 2) + 5*pow(x, 2) - pow(y, 4) + "
    "5*pow(y, 2) - 2)")
HARMONIC_3D = ("2*(x + z)", "-2*y", "2*x")

# 2D, on the square [-1, 1]^2, with b = (1-x^2)(1-y^2): u0 = b (1 + x + 2y),
# a0 = b (1/2 - x + y), h = x^2 - y^2 + xy; the rotated part is J grad(a0).
CURL_FREE_2D = ("(y - 1)*(y + 1)*(3*pow(x, 2) + 4*x*y + 2*x - 1)",
                "2*(x - 1)*(x + 1)*(x*y + 3*pow(y, 2) + y - 1)", "0")
DIVERGENCE_FREE_2D = ("(x - 1)*(x + 1)*(2*x*y - 3*pow(y, 2) - y + 1)",
                      "-(y - 1)*(y + 1)*(3*pow(x, 2) - 2*x*y - x - 1)", "0")
HARMONIC_2D = ("2*x + y", "x - 2*y", "0")


def python_function(expressions):
    """The expressions (ExprTk's pow) as a Python function of x, y, z."""
    code = [compile(e, "<expression>", "eval") for e in expressions]
    return lambda x, y, z: [eval(c, {"pow": pow}, {"x": x, "y": y, "z": z}) for c in code]


def vector_expression(*parts):
    """The sum of the parts as one ExprTk vector expression."""
    components = ["(" + " + ".join("(%s)" % p[c] for p in parts) + ")" for c in range(3)]
    return "%s*iHat + %s*jHat + %s*kHat" % tuple(components)


def cube_boundary():
    cube = vtkCubeSource()
    cube.SetBounds(-1, 1, -1, 1, -1, 1)
    cube.Update()
    return cube.GetOutput()


def square_boundary(segments_per_side=4):
    """The square [-1, 1]^2 in z = 0 as one closed polyline."""
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    vertices = []
    for k in range(4):
        (x0, y0), (x1, y1) = corners[k], corners[(k + 1) % 4]
        for s in range(segments_per_side):
            t = s / segments_per_side
            vertices.append((x0 + t * (x1 - x0), y0 + t * (y1 - y0)))
    return closed_polyline(vertices)


def probe_points(count, dimension, extent=0.8):
    """`count` points spread over [-extent, extent]^dimension (a fixed
    low-discrepancy pattern, so the test never changes)."""
    points = []
    for i in range(count):
        coordinates = [((i + 0.5) * a) % 1.0 for a in (0.7548776662, 0.5698402910, 0.3141592653)]
        p = [extent * (2.0 * c - 1.0) for c in coordinates]
        points.append((p[0], p[1], p[2] if dimension == 3 else 0.0))
    return point_cloud(points)


def decompose(boundary, probe, expression=None, field=None, walks=2048, threads=0, seed=3):
    helmholtz = gridfree.vtkWalkOnSpheresHelmholtzDecomposition()
    helmholtz.SetBoundaryData(boundary)
    helmholtz.SetProbeData(probe)
    if field is not None:
        helmholtz.SetFieldData(field)
        helmholtz.SetInputArrayToProcess(0, 2, 0, POINTS, "Velocity")
    else:
        helmholtz.SetFieldExpression(expression)
    helmholtz.SetWalksPerPoint(walks)
    helmholtz.SetNumberOfThreads(threads)
    helmholtz.SetSeed(seed)
    catcher = MessageCatcher(helmholtz)
    helmholtz.Update()
    assert not catcher.errors, catcher.error_text()
    return helmholtz.GetOutput(), helmholtz


def check_parts(output, name, parts, dimension):
    """Every component of every part within 5 standard errors of the exact
    part; returns the z-scores."""
    data = output.GetPointData()
    scores = []
    for suffix, exact in parts:
        values = data.GetArray(name + suffix)
        variances = data.GetArray(name + suffix + "_Variance")
        assert values is not None and variances is not None, suffix
        for i in range(output.GetNumberOfPoints()):
            truth = exact(*output.GetPoint(i))
            for c in range(dimension):
                sigma = math.sqrt(variances.GetComponent(i, c))
                error = values.GetComponent(i, c) - truth[c]
                assert sigma > 0.0, (suffix, i, c)
                assert abs(error) < 5.0 * sigma, (suffix, i, c, error, sigma)
                scores.append(error / sigma)
            for c in range(dimension, 3):
                assert values.GetComponent(i, c) == 0.0
    return scores


def check_sum(output, name):
    data = output.GetPointData()
    x = data.GetArray(name)
    parts = [data.GetArray(name + s) for s in ("_CurlFree", "_DivergenceFree", "_Harmonic")]
    for i in range(output.GetNumberOfPoints()):
        for c in range(3):
            total = sum(p.GetComponent(i, c) for p in parts)
            assert abs(total - x.GetComponent(i, c)) <= 1e-12 * (1.0 + abs(total))


def test_cube_parts_recovered():
    probe = probe_points(24, 3)
    expression = vector_expression(CURL_FREE_3D, DIVERGENCE_FREE_3D, HARMONIC_3D)
    output, helmholtz = decompose(cube_boundary(), probe, expression=expression)
    scores = check_parts(output, "X", [
        ("_CurlFree", python_function(CURL_FREE_3D)),
        ("_DivergenceFree", python_function(DIVERGENCE_FREE_3D)),
        ("_Harmonic", python_function(HARMONIC_3D))], 3)
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.6 < mean_z2 < 1.5, mean_z2
    check_sum(output, "X")
    # The estimates resolve the parts (median |part| over 5 times the median
    # standard error): a decomposition that dropped or swapped a part could
    # not pass the 5-sigma checks above.
    data = output.GetPointData()
    for suffix in ("_CurlFree", "_DivergenceFree", "_Harmonic"):
        values = data.GetArray("X" + suffix)
        variances = data.GetArray("X" + suffix + "_Variance")
        sizes = sorted(math.sqrt(sum(values.GetComponent(i, c) ** 2 for c in range(3)))
                       for i in range(24))
        sigmas = sorted(math.sqrt(sum(variances.GetComponent(i, c) for c in range(3)))
                        for i in range(24))
        assert sizes[12] > 5.0 * sigmas[12], (suffix, sizes[12], sigmas[12])
    field_data = output.GetFieldData()
    assert field_data.GetArray("TotalWalks").GetValue(0) == 2 * 24 * 2048
    assert helmholtz.GetLastNumberOfWalks() == 2 * 24 * 2048
    # The potentials: u0 itself (zero on the faces) and the vector potential.
    potential = data.GetArray("X_Potential")
    potential_variance = data.GetArray("X_Potential_Variance")
    for i in range(24):
        x, y, z = output.GetPoint(i)
        u0 = (1 - x * x) * (1 - y * y) * (1 - z * z) * (1 + x + 2 * y)
        assert abs(potential.GetValue(i) - u0) < 5 * math.sqrt(potential_variance.GetValue(i))
    assert data.GetArray("X_VectorPotential").GetNumberOfComponents() == 3


def test_square_parts_recovered():
    probe = probe_points(40, 2, extent=0.9)
    expression = vector_expression(CURL_FREE_2D, DIVERGENCE_FREE_2D, HARMONIC_2D)
    output, _ = decompose(square_boundary(), probe, expression=expression, walks=1024)
    scores = check_parts(output, "X", [
        ("_CurlFree", python_function(CURL_FREE_2D)),
        ("_DivergenceFree", python_function(DIVERGENCE_FREE_2D)),
        ("_Harmonic", python_function(HARMONIC_2D))], 2)
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.6 < mean_z2 < 1.5, mean_z2
    check_sum(output, "X")
    assert output.GetPointData().GetArray("X_StreamFunction") is not None


def multilinear_image():
    """X = (xyz, xz - y, xy + z) on an image covering the cube: trilinear
    interpolation reproduces it exactly, derivatives included."""
    image = vtkImageData()
    image.SetOrigin(-1.25, -1.25, -1.25)
    image.SetSpacing(0.25, 0.25, 0.25)
    image.SetDimensions(11, 11, 11)
    velocity = vtkDoubleArray()
    velocity.SetName("Velocity")
    velocity.SetNumberOfComponents(3)
    for i in range(image.GetNumberOfPoints()):
        x, y, z = image.GetPoint(i)
        velocity.InsertNextTuple((x * y * z, x * z - y, x * y + z))
    image.GetPointData().AddArray(velocity)
    return image


def test_image_field_equals_expression():
    probe = probe_points(8, 3)
    from_image, _ = decompose(cube_boundary(), probe, field=multilinear_image(), walks=256)
    from_expression, _ = decompose(
        cube_boundary(), probe, expression="x*y*z*iHat + (x*z - y)*jHat + (x*y + z)*kHat",
        walks=256)
    for suffix in ("", "_CurlFree", "_DivergenceFree", "_Harmonic"):
        a = from_image.GetPointData().GetArray("Velocity" + suffix)
        b = from_expression.GetPointData().GetArray("X" + suffix)
        for i in range(8):
            for c in range(3):
                assert abs(a.GetComponent(i, c) - b.GetComponent(i, c)) < 1e-6, (suffix, i, c)
    # Not a trivial agreement: the parts are not zero (curl X = (0, y(x - 1),
    # z(1 - x)); div X = yz is smaller).
    solenoidal = from_image.GetPointData().GetArray("Velocity_DivergenceFree")
    assert max(abs(solenoidal.GetComponent(i, c)) for i in range(8) for c in range(3)) > 0.05


def test_same_result_for_any_thread_count():
    probe = probe_points(6, 3)
    expression = vector_expression(CURL_FREE_3D, DIVERGENCE_FREE_3D, HARMONIC_3D)
    one, _ = decompose(cube_boundary(), probe, expression=expression, walks=64, threads=1)
    two, _ = decompose(cube_boundary(), probe, expression=expression, walks=64, threads=2)
    for suffix in ("_CurlFree", "_DivergenceFree", "_Harmonic_Variance"):
        a = one.GetPointData().GetArray("X" + suffix)
        b = two.GetPointData().GetArray("X" + suffix)
        for i in range(6):
            assert a.GetTuple3(i) == b.GetTuple3(i)


def cache_probe(count, dimension):
    """`count` spread points and two near the boundary: in 3D within the
    cache's shell (they take their own walks), in 2D 0.03 and 0.04 from it
    (the finest spheres answer them)."""
    probe = probe_points(count, dimension, extent=0.95)
    points = probe.GetPoints()
    near = ((0.99, 0.1, -0.2), (-0.2, 0.985, 0.5)) if dimension == 3 else \
        ((0.97, 0.1, 0.0), (-0.2, 0.96, 0.0))
    for p in near:
        points.InsertNextPoint(*p)
    return point_cloud([points.GetPoint(i) for i in range(points.GetNumberOfPoints())])


def sphere_cache_decomposition(boundary, probe, expression, seed):
    helmholtz = gridfree.vtkWalkOnSpheresHelmholtzDecomposition()
    helmholtz.SetBoundaryData(boundary)
    helmholtz.SetProbeData(probe)
    helmholtz.SetFieldExpression(expression)
    helmholtz.SetEstimator(helmholtz.SPHERE_CACHE)
    helmholtz.SetWalksPerSphere(256)
    helmholtz.SetWalksPerPoint(256)
    helmholtz.SetSeed(seed)
    catcher = MessageCatcher(helmholtz)
    helmholtz.Update()
    assert not catcher.errors, catcher.error_text()
    return helmholtz


def field_value(output, name):
    return output.GetFieldData().GetArray(name).GetValue(0)


def test_sphere_cache_parts_calibrated():
    """The Sphere Cache's parts on the cube and the square, near the
    boundary too: every value within 5 standard errors, and the reported
    variances right over three independent caches (points of one sphere
    share its walks, so one cache's points are correlated)."""
    cases = [
        (cube_boundary(), cache_probe(40, 3), 3,
         vector_expression(CURL_FREE_3D, DIVERGENCE_FREE_3D, HARMONIC_3D),
         [("_CurlFree", python_function(CURL_FREE_3D)),
          ("_DivergenceFree", python_function(DIVERGENCE_FREE_3D)),
          ("_Harmonic", python_function(HARMONIC_3D))]),
        (square_boundary(), cache_probe(60, 2), 2,
         vector_expression(CURL_FREE_2D, DIVERGENCE_FREE_2D, HARMONIC_2D),
         [("_CurlFree", python_function(CURL_FREE_2D)),
          ("_DivergenceFree", python_function(DIVERGENCE_FREE_2D)),
          ("_Harmonic", python_function(HARMONIC_2D))]),
    ]
    for boundary, probe, dimension, expression, parts in cases:
        scores = []
        for seed in range(3):
            helmholtz = sphere_cache_decomposition(boundary, probe, expression, seed)
            output = helmholtz.GetOutput()
            scores += check_parts(output, "X", parts, dimension)
            check_sum(output, "X")
            n = probe.GetNumberOfPoints()
            from_cache = [output.GetPointData().GetArray("FromBoundaryCache").GetValue(i)
                          for i in range(n)]
            walked = 2 if dimension == 3 else 0
            assert from_cache == [1] * (n - walked) + [0] * walked
            assert field_value(output, "PointsFromCache") == n - walked
            assert field_value(output, "PointsWalkedInShell") == walked
            assert field_value(output, "CacheWalksRun") > 0
        mean_z2 = sum(z * z for z in scores) / len(scores)
        assert 0.7 < mean_z2 < 1.4, (dimension, mean_z2)


def test_sphere_cache_reused_by_moved_probe():
    """A second probe inside the spheres already made runs no walks in the
    caches (CacheWalksRun 0) and answers each point as before; a probe that
    reaches new spheres makes them."""
    expression = vector_expression(CURL_FREE_3D, DIVERGENCE_FREE_3D, HARMONIC_3D)
    probe = probe_points(30, 3, extent=0.6)
    helmholtz = sphere_cache_decomposition(cube_boundary(), probe, expression, 5)
    first = helmholtz.GetOutput()
    before = [first.GetPointData().GetArray("X_DivergenceFree").GetTuple3(i) for i in range(30)]
    assert field_value(first, "CacheWalksRun") > 0
    subset = list(range(29, -1, -3))
    helmholtz.SetProbeData(point_cloud([probe.GetPoint(i) for i in subset]))
    helmholtz.Update()
    second = helmholtz.GetOutput()
    assert field_value(second, "CacheWalksRun") == 0
    assert helmholtz.GetLastNumberOfWalks() == 0
    for k, i in enumerate(subset):
        assert second.GetPointData().GetArray("X_DivergenceFree").GetTuple3(k) == before[i]
    helmholtz.SetProbeData(point_cloud([(0.8, -0.8, 0.75)]))
    helmholtz.Update()
    assert field_value(helmholtz.GetOutput(), "CacheWalksRun") > 0


def run_expecting_error(configure):
    helmholtz = gridfree.vtkWalkOnSpheresHelmholtzDecomposition()
    helmholtz.SetBoundaryData(cube_boundary())
    helmholtz.SetProbeData(probe_points(3, 3))
    helmholtz.SetWalksPerPoint(4)
    configure(helmholtz)
    catcher = MessageCatcher(helmholtz)
    helmholtz.Update()
    return catcher


def test_errors():
    catcher = run_expecting_error(lambda h: None)
    assert "No vector field" in catcher.error_text()
    catcher = run_expecting_error(lambda h: h.SetFieldExpression("x + y"))
    assert "vector field" in catcher.error_text(), catcher.error_text()
    catcher = run_expecting_error(lambda h: h.SetFieldExpression("x +* iHat"))
    assert "does not parse" in catcher.error_text(), catcher.error_text()
    scalar_image = vtkImageData()
    scalar_image.SetDimensions(3, 3, 3)
    scalar_image.SetOrigin(-1, -1, -1)
    scalars = vtkDoubleArray()
    scalars.SetName("s")
    scalars.SetNumberOfTuples(27)
    scalars.Fill(1.0)
    scalar_image.GetPointData().SetScalars(scalars)
    catcher = run_expecting_error(lambda h: h.SetFieldData(scalar_image))
    assert "no vector point array" in catcher.error_text(), catcher.error_text()
    catcher = run_expecting_error(lambda h: (h.SetFieldExpression("x*iHat"),
                                             h.SetEstimator(h.BOUNDARY_CACHE)))
    assert "not the Boundary Cache" in catcher.error_text(), catcher.error_text()
    empty = vtkPolyData()
    helmholtz = gridfree.vtkWalkOnSpheresHelmholtzDecomposition()
    helmholtz.SetBoundaryData(empty)
    helmholtz.SetProbeData(probe_points(3, 3))
    helmholtz.SetFieldExpression("x*iHat")
    catcher = MessageCatcher(helmholtz)
    helmholtz.Update()
    assert "No Boundary" in catcher.error_text()


def test_solver_vector_source_expression():
    """The solver's vector SourceExpression (what the decomposition builds
    on): Laplacian u_c = f_c with f = (6, 12, -6) and u = 0 on the unit
    sphere gives u = (r^2 - 1)(1, 2, -1)."""
    from gridfree_testing import filled_array, sphere_boundary
    boundary = sphere_boundary(resolution=96)
    boundary.GetPointData().AddArray(
        filled_array("U", boundary.GetNumberOfPoints(), 0.0, components=3))
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetInputData(0, boundary)
    solver.SetInputData(1, probe_points(12, 3, extent=0.5))
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "U")
    solver.SetEquationToPoisson()
    solver.SetSourceExpression("6*iHat + 12*jHat - 6*kHat")
    solver.SetWalksPerPoint(512)
    catcher = MessageCatcher(solver)
    solver.Update()
    assert not catcher.errors, catcher.error_text()
    output = solver.GetOutput()
    values = output.GetPointData().GetArray("U")
    variances = output.GetPointData().GetArray("U_Variance")
    for i in range(12):
        x, y, z = output.GetPoint(i)
        r2 = x * x + y * y + z * z
        for c, k in enumerate((1.0, 2.0, -1.0)):
            error = values.GetComponent(i, c) - (r2 - 1.0) * k
            assert abs(error) < 5.0 * math.sqrt(variances.GetComponent(i, c)), (i, c, error)
    # A vector source needs a 3-component solution.
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    boundary.GetPointData().AddArray(filled_array("T", boundary.GetNumberOfPoints(), 0.0))
    solver.Modified()
    solver.Update()
    assert "is a vector" in catcher.error_text(), catcher.error_text()
