"""Mixed boundary conditions through the solver's VTK API (walk on stars,
Documentation/WalkOnStars.md): Dirichlet, Neumann and Robin cells of one
mesh chosen by a condition array, against harmonic closed forms (|z| < 5,
mean z^2 near 1): values, gradients and Hessians, from the sphere cache, the
stream tracer and the adaptive sampler; and the messages of what cannot
work."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkCellArray, vtkDataObject, vtkPlane, vtkPolyData, vtkSphere)
from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkTriangleFilter  # noqa: E402
from vtkmodules.vtkFiltersSources import (  # noqa: E402
    vtkPlaneSource, vtkSphereSource, vtkTessellatedBoxSource)

from gridfree_testing import MessageCatcher, add_point_array, z_scores  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
CELLS = vtkDataObject.FIELD_ASSOCIATION_CELLS
SOLVER = gridfree.vtkWalkOnSpheresSolver
ROBIN = 2.0  # the Robin coefficient on the z faces


def u3(x, y, z):
    return x * x - y * y + 0.5 * z


def grad3(x, y, z):
    return (2.0 * x, -2.0 * y, 0.5)


def face_normal(c):
    """The outward normal of the face of [-0.5, 0.5]^3 a cell centre lies on."""
    axis = max(range(3), key=lambda k: abs(c[k]))
    n = [0.0, 0.0, 0.0]
    n[axis] = 1.0 if c[axis] > 0 else -1.0
    return axis, n


def cell_centre(mesh, cell):
    ids = mesh.GetCell(cell).GetPointIds()
    pts = [mesh.GetPoint(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]
    return [sum(p[k] for p in pts) / len(pts) for k in range(3)]


def box(level=12):
    """The cube [-0.5, 0.5]^3, outward triangles, each face with its own
    points: T = u everywhere, bc = 0 on the x faces (Dirichlet), 1 on the y
    faces (Neumann), 2 on the z faces (Robin, mu = ROBIN), and the flux h =
    du/dn + mu u at each face's points."""
    source = vtkTessellatedBoxSource()
    source.SetBounds(-0.5, 0.5, -0.5, 0.5, -0.5, 0.5)
    source.SetLevel(level)
    source.QuadsOff()
    source.DuplicateSharedPointsOn()
    source.Update()
    mesh = vtkPolyData()
    mesh.DeepCopy(source.GetOutput())
    add_point_array(mesh, "T", u3)
    bc = vtkIntArray()
    bc.SetName("bc")
    mu = vtkDoubleArray()
    mu.SetName("mu")
    point_normal = {}
    for cell in range(mesh.GetNumberOfCells()):
        axis, n = face_normal(cell_centre(mesh, cell))
        bc.InsertNextValue(axis)  # x faces 0, y faces 1, z faces 2
        mu.InsertNextValue(ROBIN if axis == 2 else 0.0)
        ids = mesh.GetCell(cell).GetPointIds()
        for k in range(ids.GetNumberOfIds()):
            point_normal[ids.GetId(k)] = (axis, n)
    mesh.GetCellData().AddArray(bc)
    mesh.GetCellData().AddArray(mu)
    h = vtkDoubleArray()
    h.SetName("h")
    for i in range(mesh.GetNumberOfPoints()):
        p = mesh.GetPoint(i)
        axis, n = point_normal[i]
        flux = sum(g * nk for g, nk in zip(grad3(*p), n))
        h.InsertNextValue(flux + (ROBIN * u3(*p) if axis == 2 else 0.0))
    mesh.GetPointData().AddArray(h)
    return mesh


def cloud(count, half=0.4, outside=()):
    """Deterministic points in the cube [-half, half]^3, then `outside`."""
    points = vtkPoints()
    for i in range(count):
        # A Halton-like low-discrepancy sequence in bases 2, 3, 5.
        coords = []
        for base in (2, 3, 5):
            f, r, n = 1.0, 0.0, i + 1
            while n > 0:
                f /= base
                r += f * (n % base)
                n //= base
            coords.append((2.0 * r - 1.0) * half)
        points.InsertNextPoint(*coords)
    for p in outside:
        points.InsertNextPoint(*p)
    data = vtkPolyData()
    data.SetPoints(points)
    return data


def with_conditions(algorithm, boundary):
    """`algorithm` (solver, stream tracer or sampler) on `boundary` with
    the box's arrays: values T, conditions bc, flux h, Robin mu."""
    algorithm.SetBoundaryData(boundary)
    algorithm.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    algorithm.SetMixedBoundaryConditions(True)
    algorithm.SetInputArrayToProcess(4, 0, 0, CELLS, "bc")
    algorithm.SetInputArrayToProcess(5, 0, 0, POINTS, "h")
    algorithm.SetInputArrayToProcess(6, 0, 0, CELLS, "mu")
    return algorithm


def mixed_solver(boundary, probe, walks=128):
    solver = with_conditions(SOLVER(), boundary)
    solver.SetProbeData(probe)
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(11)
    return solver


def field(output, name):
    return output.GetFieldData().GetArray(name).GetTuple1(0)


def assert_calibrated(scores):
    assert max(abs(z) for z in scores) < 5.0, max(abs(z) for z in scores)
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.7 < mean_z2 < 1.4, mean_z2


def flux_solver(probe, association, seed, walks=256):
    """A solver on `probe` (its Boundary still to be set) with values T and
    the conditions bc and flux h, both with `association`."""
    solver = SOLVER()
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetMixedBoundaryConditions(True)
    solver.SetInputArrayToProcess(4, 0, 0, association, "bc")
    solver.SetInputArrayToProcess(5, 0, 0, association, "h")
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(seed)
    return solver


def assert_solves_calibrated(solver, exact):
    catcher = MessageCatcher(solver)
    solver.Update()
    assert not catcher.errors, catcher.error_text()
    assert_calibrated(z_scores(solver.GetOutput(), exact))


def test_dirichlet_neumann_and_robin_faces_of_a_box():
    outside = [(0.9, 0.0, 0.0), (0.0, -0.8, 0.3)]
    solver = mixed_solver(box(), cloud(150, outside=outside))
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    n = out.GetNumberOfPoints()
    scores = z_scores(out, u3)[: n - len(outside)]
    assert_calibrated(scores)
    # Points outside the closed boundary get the exterior problem's answer
    # (checked against a closed form in the Robin exterior test below).
    values = out.GetPointData().GetArray("T")
    assert all(math.isfinite(values.GetTuple1(i)) for i in range(n - len(outside), n))
    assert field(out, "OutsidePoints") == 0
    assert "lie outside the closed boundary" not in catcher.warning_text()
    assert field(out, "BackFaceHits") == 0


CHARGE = (0.1, 0.05, -0.1)  # inside the box


def potential(x, y, z):
    return 1.0 / math.dist((x, y, z), CHARGE)


def potential_gradient(x, y, z):
    d = (x - CHARGE[0], y - CHARGE[1], z - CHARGE[2])
    r3 = math.dist((x, y, z), CHARGE) ** 3
    return tuple(-dk / r3 for dk in d)


SQRT_C = 2.0  # of the screened exterior test


def yukawa(x, y, z):
    r = math.dist((x, y, z), CHARGE)
    return math.exp(-SQRT_C * r) / r


def yukawa_gradient(x, y, z):
    r = math.dist((x, y, z), CHARGE)
    scale = -(1.0 / r + SQRT_C) * math.exp(-SQRT_C * r) / (r * r)
    return tuple(scale * (p - a) for p, a in zip((x, y, z), CHARGE))


def potential_box(u=potential, gradient=potential_gradient, exterior_robin=False):
    """The box of box() with T = u, by default 1/|x - a| (a inside:
    harmonic outside, 0 at infinity), Dirichlet x faces and Neumann y and z
    faces with the flux h = dT/dn at each face's points. With
    `exterior_robin`, the z faces are Robin (mu = ROBIN) for the exterior
    problem: h = dT/dn' + mu T along the normal n' out of the exterior
    domain (the opposite of the mesh's)."""
    mesh = box(level=10)
    mesh.GetPointData().RemoveArray("T")
    mesh.GetPointData().RemoveArray("h")
    add_point_array(mesh, "T", u)
    bc = mesh.GetCellData().GetArray("bc")
    point_normal = {}
    for cell in range(mesh.GetNumberOfCells()):
        axis, n = face_normal(cell_centre(mesh, cell))
        robin = exterior_robin and axis == 2
        bc.SetValue(cell, 0 if axis == 0 else (2 if robin else 1))
        ids = mesh.GetCell(cell).GetPointIds()
        for k in range(ids.GetNumberOfIds()):
            point_normal[ids.GetId(k)] = (n, robin)
    h = vtkDoubleArray()
    h.SetName("h")
    for i in range(mesh.GetNumberOfPoints()):
        p = mesh.GetPoint(i)
        n, robin = point_normal[i]
        flux = sum(g * nk for g, nk in zip(gradient(*p), n))
        h.InsertNextValue(ROBIN * u(*p) - flux if robin else flux)
    mesh.GetPointData().AddArray(h)
    return mesh


def shell_points(count):
    """Points 0.1 to 0.7 outside the box [-0.5, 0.5]^3 (max-norm 0.6 to 1.2)."""
    points = []
    for i in range(count):
        z = 1.0 - 2.0 * (i + 0.5) / count
        phi = 2.399963 * i  # the golden angle
        d = (math.sqrt(1 - z * z) * math.cos(phi), math.sqrt(1 - z * z) * math.sin(phi), z)
        r = 0.6 + 0.6 * ((i * 0.618034) % 1.0)
        scale = r / max(abs(c) for c in d)
        points.append(tuple(scale * c for c in d))
    return points


def test_points_outside_get_the_exterior_problems_answer():
    # Laplace without Robin parts: as walk on spheres answers both sides of
    # a Dirichlet boundary, points outside the closed boundary walk on stars
    # in its exterior (u -> 0 at infinity), with the same condition arrays.
    outside = shell_points(150)
    inside = 30
    solver = mixed_solver(potential_box(), cloud(inside, half=0.35, outside=outside), walks=256)
    solver.SetComputeGradient(True)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert "lie outside the closed boundary" not in catcher.warning_text()
    assert field(out, "OutsidePoints") == 0
    assert field(out, "BackFaceHits") == 0
    assert_calibrated(z_scores(out, potential)[inside:])
    assert_calibrated(component_z_scores(out, "T_Gradient", potential_gradient, range(3))[3 * inside:])
    values = out.GetPointData().GetArray("T")
    assert all(math.isfinite(values.GetTuple1(i)) for i in range(inside))


def test_points_outside_get_the_robin_exterior_problems_answer():
    # Robin z faces outside: the condition holds along the normal out of
    # the exterior domain, so mu > 0 keeps its meaning on either side.
    outside = shell_points(150)
    solver = mixed_solver(potential_box(exterior_robin=True), cloud(0, outside=outside),
                          walks=256)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert field(out, "OutsidePoints") == 0
    assert field(out, "BackFaceHits") == 0
    assert_calibrated(z_scores(out, potential))


def test_points_outside_get_the_screened_exterior_problems_answer():
    # The screened equation without a source too: e^{-sqrt(c) r}/r outside.
    outside = shell_points(150)
    solver = mixed_solver(potential_box(yukawa, yukawa_gradient), cloud(0, outside=outside),
                          walks=256)
    solver.SetEquation(SOLVER.SCREENED_POISSON)
    solver.SetScreeningCoefficient(SQRT_C * SQRT_C)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert field(out, "OutsidePoints") == 0
    assert_calibrated(z_scores(out, yukawa))
    # A source: the exterior is not solved, and points outside are NaN.
    solver.SetSourceExpression("1")
    solver.Update()
    assert field(solver.GetOutput(), "OutsidePoints") == len(outside)
    assert "lie outside the closed boundary" in catcher.warning_text()


def hessian3(x, y, z):
    return (2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0)


def component_z_scores(output, name, exact, components):
    """z of every component `components` of array `name` at every point."""
    values = output.GetPointData().GetArray(name)
    variances = output.GetPointData().GetArray(name + "_Variance")
    scores = []
    for i in range(output.GetNumberOfPoints()):
        want = exact(*output.GetPoint(i))
        for k in components:
            scores.append((values.GetComponent(i, k) - want[k])
                          / math.sqrt(variances.GetComponent(i, k)))
    return scores


def test_gradient_and_hessian_with_mixed_conditions():
    # A first ball clear of every face, then walk on stars: the value, each
    # gradient component and the Hessian's upper triangle, calibrated.
    solver = mixed_solver(box(), cloud(120), walks=256)
    solver.SetComputeGradient(True)
    solver.SetComputeHessian(True)
    solver.SetComputeDirectionalDerivative(True)
    direction = (0.6, -0.8, 0.5)
    solver.SetDerivativeDirection(*direction)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert_calibrated(z_scores(out, u3))
    assert_calibrated(component_z_scores(out, "T_Gradient", grad3, range(3)))
    assert_calibrated(component_z_scores(out, "T_Hessian", hessian3, (0, 1, 2, 4, 5, 8)))
    assert_calibrated(z_scores(
        out, lambda x, y, z: sum(d * g for d, g in zip(direction, grad3(x, y, z))),
        name="T_DirectionalDerivative"))
    assert field(out, "BackFaceHits") == 0


def test_the_stream_tracer_and_adaptive_sampler_take_mixed_conditions():
    mesh = box()
    # Lines of grad u = (2x, -2y, 0.5) keep x y constant.
    tracer = with_conditions(gridfree.vtkWalkOnSpheresStreamTracer(), mesh)
    tracer.SetSeed(3)
    seeds = cloud(4, half=0.25)
    tracer.SetSeedsData(seeds)
    tracer.SetWalksPerPoint(1024)
    tracer.SetStepLength(0.03)
    tracer.SetStepLengthIsRelative(False)
    tracer.SetMaximumPropagation(0.3)
    catcher = MessageCatcher(tracer)
    tracer.Update()
    assert not catcher.errors, catcher.error_text()
    lines = tracer.GetOutput()
    assert lines.GetNumberOfPoints() > 4 * 5
    seed_ids = lines.GetCellData().GetArray("SeedIds")
    for cell in range(lines.GetNumberOfCells()):
        x0, y0, _ = seeds.GetPoint(int(seed_ids.GetValue(cell)))
        ids = lines.GetCell(cell).GetPointIds()
        for k in range(ids.GetNumberOfIds()):
            x, y, _ = lines.GetPoint(ids.GetId(k))
            assert abs(x * y - x0 * y0) < 0.01, (x * y, x0 * y0)
    assert_calibrated(z_scores(lines, u3) + component_z_scores(lines, "T_Gradient", grad3, range(3)))

    sampler = with_conditions(gridfree.vtkWalkOnSpheresAdaptiveSampler(), mesh)
    sampler.SetSeed(3)
    sampler.SetDomainData(cloud(300))
    sampler.SetWalksPerPoint(256)
    sampler.SetInitialSamples(48)
    sampler.SetMaximumSamples(96)
    catcher = MessageCatcher(sampler)
    sampler.Update()
    assert not catcher.errors, catcher.error_text()
    samples = sampler.GetOutput()
    assert samples.GetNumberOfPoints() == 96
    assert_calibrated(z_scores(samples, u3))


def test_the_sphere_cache_answers_mixed_conditions():
    # The spheres keep clear of the whole boundary and their samples walk
    # on stars: the same box, every inside point from the cache or its shell.
    outside = [(0.9, 0.0, 0.0)]
    solver = mixed_solver(box(), cloud(150, outside=outside), walks=256)
    solver.SetEstimator(SOLVER.SPHERE_CACHE)
    solver.SetWalksPerSphere(256)
    solver.SetComputeGradient(True)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    n = out.GetNumberOfPoints()
    assert_calibrated(z_scores(out, u3)[: n - len(outside)])
    # The gradient too: from the spheres, and in the shell from a first
    # ball and walks on stars.
    assert_calibrated(component_z_scores(out, "T_Gradient", grad3, range(3))[: 3 * (n - len(outside))])
    assert field(out, "PointsFromCache") + field(out, "PointsWalkedInShell") == n - len(outside)
    assert field(out, "CacheSpheres") > 0
    assert field(out, "OutsidePoints") == len(outside)
    assert math.isnan(out.GetPointData().GetArray("T").GetTuple1(n - 1))


def test_a_wrong_flux_sign_is_detected():
    # The flux taken along the inward normal: the estimate must move off
    # the solution (the test above is not passing by accident).
    mesh = box()
    h = mesh.GetPointData().GetArray("h")
    bc = mesh.GetCellData().GetArray("bc")
    flipped = vtkDoubleArray()
    flipped.DeepCopy(h)
    flipped.SetName("h_flipped")
    neumann_points = set()
    for cell in range(mesh.GetNumberOfCells()):
        if bc.GetValue(cell) == 1:
            ids = mesh.GetCell(cell).GetPointIds()
            neumann_points.update(ids.GetId(k) for k in range(3))
    for i in neumann_points:
        flipped.SetValue(i, -h.GetValue(i))
    mesh.GetPointData().AddArray(flipped)
    solver = mixed_solver(mesh, cloud(150))
    solver.SetInputArrayToProcess(5, 0, 0, POINTS, "h_flipped")
    solver.Update()
    scores = z_scores(solver.GetOutput(), u3)
    assert sum(z * z for z in scores) / len(scores) > 4.0


def faces_points(mesh, axis):
    """The point ids of the cells on the faces normal to `axis` (each face
    has its own points)."""
    bc = mesh.GetCellData().GetArray("bc")
    points = set()
    for cell in range(mesh.GetNumberOfCells()):
        if bc.GetValue(cell) == axis:
            ids = mesh.GetCell(cell).GetPointIds()
            points.update(ids.GetId(k) for k in range(ids.GetNumberOfIds()))
    return sorted(points)


def quick_solve(mesh):
    """A small solve on `mesh`: its messages."""
    solver = mixed_solver(mesh, cloud(10), walks=16)
    catcher = MessageCatcher(solver)
    solver.Update()
    return catcher


def test_a_non_finite_flux_or_robin_coefficient_is_an_error_that_says_where():
    nan, inf = float("nan"), float("inf")
    # NaN and infinite flux at three points of the Neumann faces.
    mesh = box(level=4)
    h = mesh.GetPointData().GetArray("h")
    neumann = faces_points(mesh, 1)
    for i, value in zip(neumann[:3], (nan, inf, -inf)):
        h.SetValue(i, value)
    catcher = quick_solve(mesh)
    text = catcher.error_text()
    assert "the Neumann flux is nan at point %d" % neumann[0] in text, text
    assert "(and at 2 more points of Neumann and Robin cells)" in text, text
    assert "overflowed" not in text + catcher.warning_text()
    # Where the flux is not used (points of Dirichlet faces only), NaN is fine.
    mesh = box(level=4)
    h = mesh.GetPointData().GetArray("h")
    for i in faces_points(mesh, 0)[:5]:
        h.SetValue(i, nan)
    catcher = quick_solve(mesh)
    assert not catcher.errors, catcher.error_text()
    # A Robin coefficient of NaN on three Robin cells.
    mesh = box(level=4)
    mu, bc = mesh.GetCellData().GetArray("mu"), mesh.GetCellData().GetArray("bc")
    robin = [c for c in range(mesh.GetNumberOfCells()) if bc.GetValue(c) == 2]
    for c in robin[:3]:
        mu.SetValue(c, nan)
    text = quick_solve(mesh).error_text()
    assert "the Robin coefficient of cell %d is nan" % robin[0] in text, text
    assert "(and at 2 more Robin cells)" in text, text


def test_a_flux_out_of_all_proportion_is_warned():
    mesh = box(level=4)
    assert "Neumann flux reaches" not in quick_solve(mesh).warning_text()
    h = mesh.GetPointData().GetArray("h")
    for i in faces_points(mesh, 1)[:4]:
        h.SetValue(i, 1e300)
    mesh.Modified()
    text = quick_solve(mesh).warning_text()
    assert "The Neumann flux reaches 1e+300" in text, text


def test_neumann_cells_met_from_outside_are_counted():
    # The mesh turned inside out: every normal points into the box.
    mesh = box(level=6)
    polys = mesh.GetPolys()
    flipped = vtkCellArray()
    for cell in range(mesh.GetNumberOfCells()):
        ids = mesh.GetCell(cell).GetPointIds()
        flipped.InsertNextCell(3)
        for k in (0, 2, 1):
            flipped.InsertCellPoint(ids.GetId(k))
    assert polys.GetNumberOfCells() == flipped.GetNumberOfCells()
    mesh.SetPolys(flipped)
    solver = mixed_solver(mesh, cloud(20), walks=16)
    catcher = MessageCatcher(solver)
    solver.Update()
    assert field(solver.GetOutput(), "BackFaceHits") > 0
    assert "from outside the domain" in catcher.warning_text()


def bumpy_blob():
    """A closed, outward-oriented nonconvex blob (a 96 x 96 sphere source
    with r = 1 + 0.25 sin 5theta cos 4phi): T = x^2 - y^2 + z/2, a band
    |z| < 0.35 Robin (bc 2, mu from 0.9 to 5.3 along x, flux None), the rest
    Dirichlet."""
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(96)
    sphere.SetPhiResolution(96)
    sphere.Update()
    mesh = vtkPolyData()
    mesh.DeepCopy(sphere.GetOutput())
    points = mesh.GetPoints()
    for i in range(points.GetNumberOfPoints()):
        x, y, z = points.GetPoint(i)
        r = math.sqrt(x * x + y * y + z * z)
        scale = (1.0 + 0.25 * math.sin(5 * math.acos(z / r)) * math.cos(4 * math.atan2(y, x))) / r
        points.SetPoint(i, x * scale, y * scale, z * scale)
    add_point_array(mesh, "T", u3)
    bc, mu = vtkIntArray(), vtkDoubleArray()
    bc.SetName("bc")
    mu.SetName("mu")
    for cell in range(mesh.GetNumberOfCells()):
        x, _, z = cell_centre(mesh, cell)
        robin = abs(z) < 0.35
        bc.InsertNextValue(2 if robin else 0)
        mu.InsertNextValue(0.5 + 2.0 * (x + 1.2) if robin else 0.0)
    mesh.GetCellData().AddArray(bc)
    mesh.GetCellData().AddArray(mu)
    return mesh


def test_no_back_face_hits_on_a_closed_nonconvex_blob():
    # Walks stepping off the Robin band moved from the point on the surface,
    # not from the point the ray was traced from (1e-9 of the diagonal
    # inside): a ray that grazed a neighbouring triangle could cross it
    # within the step where the traced ray crossed beyond it, and the walk
    # left the domain. One walk of this point did so (6 back-face hits),
    # out of 51,200 walks from 100 points.
    solver = with_conditions(SOLVER(), bumpy_blob())
    solver.SetInputArrayToProcess(5, 0, 0, POINTS, "None")
    solver.SetProbeData(cloud(0, outside=[(-0.46306803822517395, 0.535327672958374,
                                           -0.15423479676246643)]))
    solver.SetEpsilon(1e-4)
    solver.SetEpsilonIsRelative(False)
    solver.SetWalksPerPoint(512)
    solver.SetSeed(2)
    solver.SetControlVariates(False)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert field(out, "BackFaceHits") == 0
    assert field(out, "OutsidePoints") == 0
    assert "from outside the domain" not in catcher.warning_text()


def test_conditions_marked_by_regions_without_expressions():
    # The cube's bottom face marked Neumann behind a plane, its top face by a
    # second marker in front of another (Inside Out), both with the flux of
    # u = x^2 - y^2 + z/2 (-0.5 and +0.5), the rest left Dirichlet: the
    # solver reads the markers' bc, h and mu and is calibrated.
    cube = vtkTessellatedBoxSource()
    cube.SetBounds(-0.5, 0.5, -0.5, 0.5, -0.5, 0.5)
    cube.SetLevel(10)
    cube.QuadsOff()
    cube.DuplicateSharedPointsOn()
    cube.Update()
    mesh = vtkPolyData()
    mesh.DeepCopy(cube.GetOutput())
    add_point_array(mesh, "T", u3)
    below, above = vtkPlane(), vtkPlane()
    below.SetOrigin(0, 0, -0.49)
    below.SetNormal(0, 0, 1)
    above.SetOrigin(0, 0, 0.49)
    above.SetNormal(0, 0, 1)
    bottom = gridfree.vtkBoundaryConditionMarker()
    bottom.SetInputData(mesh)
    bottom.SetRegion(below)
    bottom.SetFlux(-0.5)
    top = gridfree.vtkBoundaryConditionMarker()
    top.SetInputConnection(bottom.GetOutputPort())
    top.SetRegion(above)
    top.InsideOutOn()
    top.SetFlux(0.5)
    top.Update()
    marked = top.GetOutput()
    per_face = 2 * 11 * 11  # level 10: 11 divisions a side
    assert field(bottom.GetOutput(), "MarkedCells") == per_face
    assert field(marked, "MarkedCells") == per_face
    bc, h = marked.GetCellData().GetArray("bc"), marked.GetCellData().GetArray("h")
    for cell in range(marked.GetNumberOfCells()):
        z = cell_centre(marked, cell)[2]
        want = 1 if abs(abs(z) - 0.5) < 1e-9 else 0
        assert bc.GetValue(cell) == want, (cell, z)
        assert h.GetValue(cell) == (0.5 * (1 if z > 0 else -1) if want else 0.0)
    solver = flux_solver(cloud(120), CELLS, seed=6)
    solver.SetBoundaryConnection(top.GetOutputPort())
    assert_solves_calibrated(solver, u3)
    # Robin with its coefficient, inside a sphere; and no region is an error.
    ball = vtkSphere()
    ball.SetCenter(0.5, 0.5, 0.5)
    ball.SetRadius(0.3)
    corner = gridfree.vtkBoundaryConditionMarker()
    corner.SetInputData(mesh)
    corner.SetRegion(ball)
    corner.SetCondition(gridfree.vtkBoundaryConditionMarker.ROBIN)
    corner.SetRobinCoefficient(2.5)
    corner.Update()
    out = corner.GetOutput()
    mu = out.GetCellData().GetArray("mu")
    robin = [c for c in range(out.GetNumberOfCells()) if out.GetCellData().GetArray("bc").GetValue(c) == 2]
    assert 0 < len(robin) == field(out, "MarkedCells")
    assert all(mu.GetValue(c) == 2.5 for c in robin)
    empty = gridfree.vtkBoundaryConditionMarker()
    empty.SetInputData(mesh)
    catcher = MessageCatcher(empty, empty.GetExecutive())
    empty.Update()
    assert "No Region is set" in catcher.error_text()


def slit(x, y, z):
    """sqrt(r) cos(theta / 2), theta in [0, 2 pi) from the positive x axis:
    harmonic off the half-plane y = 0, x > 0, with no flux through either
    side of it, and a jump of 2 sqrt(r) across it."""
    theta = math.atan2(y, x)
    if theta < 0.0:
        theta += 2.0 * math.pi
    return math.sqrt(math.hypot(x, y)) * math.cos(0.5 * theta)


def test_an_insulating_sheet_inside_the_domain():
    # The cube [-1, 1]^3 at T = slit (Dirichlet, bc 0) and, appended to it,
    # the sheet y = 0, 0 <= x <= 1 (bc 3): the domain on both of its sides.
    cube = vtkTessellatedBoxSource()
    cube.SetBounds(-1, 1, -1, 1, -1, 1)
    cube.SetLevel(8)
    cube.QuadsOff()
    sheet = vtkPlaneSource()
    sheet.SetOrigin(0, 0, -1)
    sheet.SetPoint1(1, 0, -1)
    sheet.SetPoint2(0, 0, 1)
    sheet.SetResolution(8, 16)
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(sheet.GetOutputPort())
    both = vtkAppendPolyData()
    both.AddInputConnection(cube.GetOutputPort())
    both.AddInputConnection(triangles.GetOutputPort())
    both.Update()
    mesh = vtkPolyData()
    mesh.DeepCopy(both.GetOutput())
    mesh.GetPointData().Initialize()
    bc = vtkIntArray()
    bc.SetName("bc")
    for cell in range(mesh.GetNumberOfCells()):
        x, y, z = cell_centre(mesh, cell)
        on_sheet = abs(y) < 1e-9 and x > 1e-9 and x < 1.0 - 1e-9
        bc.InsertNextValue(3 if on_sheet else 0)
    mesh.GetCellData().AddArray(bc)
    probe = vtkPoints()
    for i in range(400):
        x, y, z = (((i * k) % 1.0) * 1.8 - 0.9 for k in (0.7548776662, 0.5698402910, 0.3819660113))
        if x > -0.05 and abs(y) < 0.05:
            continue
        probe.InsertNextPoint(x, y, z)
    points = vtkPolyData()
    points.SetPoints(probe)
    solver = SOLVER()
    solver.SetBoundaryData(mesh)
    solver.SetProbeData(points)
    # The jump along the sheet's edges on the cube: values from an
    # expression at each walk's end, not interpolated across triangles.
    solver.SetBoundaryValueExpression("sign(y)*sqrt((sqrt(x^2+y^2)+x)/2)")
    solver.SetMixedBoundaryConditions(True)
    solver.SetInputArrayToProcess(4, 0, 0, CELLS, "bc")
    solver.SetWalksPerPoint(256)
    solver.SetSeed(4)
    catcher = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert not catcher.errors, catcher.error_text()
    assert_calibrated(z_scores(out, slit, name="Solution"))
    assert field(out, "BackFaceHits") == 0
    assert field(out, "OutsidePoints") == 0
    # The sphere cache says it does not answer sheets yet.
    solver.SetEstimator(SOLVER.SPHERE_CACHE)
    catcher = MessageCatcher(solver)
    solver.Update()
    assert "insulating sheets" in catcher.error_text(), catcher.error_text()


def square_2d():
    """The square [-0.5, 0.5]^2 in z = 0, counter-clockwise (the domain on
    the left), one polyline per side of 8 segments: T = x^2 - y^2, the
    point array bc = 1 on the points of the y sides' interiors (Neumann,
    flux -1 there), 0 on the x sides and the corners."""
    points = vtkPoints()
    lines = vtkCellArray()
    corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    segments = 8
    for side in range(4):
        a, b = corners[side], corners[(side + 1) % 4]
        lines.InsertNextCell(segments + 1)
        for k in range(segments + 1):
            t = k / segments
            lines.InsertCellPoint(points.InsertNextPoint(
                a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0))
    mesh = vtkPolyData()
    mesh.SetPoints(points)
    mesh.SetLines(lines)
    add_point_array(mesh, "T", lambda x, y, z: x * x - y * y)
    bc = vtkIntArray()
    bc.SetName("bc")
    for i in range(mesh.GetNumberOfPoints()):
        x, y, _ = mesh.GetPoint(i)
        bc.InsertNextValue(1 if abs(abs(y) - 0.5) < 1e-12 and abs(x) < 0.5 - 1e-12 else 0)
    mesh.GetPointData().AddArray(bc)
    add_point_array(mesh, "h", lambda x, y, z: -1.0)
    return mesh


def test_point_conditions_in_2d():
    # Per point: a segment is Neumann only where both its points are, so the
    # segments at the corners stay Dirichlet (there u = g still holds).
    probe = vtkPolyData()
    points = vtkPoints()
    for i in range(150):
        points.InsertNextPoint(0.8 * ((i * 0.7548776662) % 1.0 - 0.5),
                               0.8 * ((i * 0.5698402910) % 1.0 - 0.5), 0.0)
    probe.SetPoints(points)
    solver = flux_solver(probe, POINTS, seed=5)
    solver.SetBoundaryData(square_2d())
    assert_solves_calibrated(solver, lambda x, y, z: x * x - y * y)


def test_points_outside_in_2d():
    # Outside the square, u = Re 1/(z - a) (a inside: harmonic outside and
    # bounded, the 2D exterior problem's kind), Dirichlet x sides and
    # Neumann y sides with its flux.
    a = (0.1, -0.05)

    def u(x, y, z):
        return (x - a[0]) / ((x - a[0]) ** 2 + (y - a[1]) ** 2)

    def flux(x, y):
        dx, dy = x - a[0], y - a[1]
        return -2.0 * dx * dy / (dx * dx + dy * dy) ** 2 * (1.0 if y > 0 else -1.0)

    mesh = square_2d()
    mesh.GetPointData().RemoveArray("T")
    mesh.GetPointData().RemoveArray("h")
    add_point_array(mesh, "T", u)
    add_point_array(mesh, "h", lambda x, y, z: flux(x, y))
    probe = vtkPolyData()
    points = vtkPoints()
    for i in range(200):  # 0.8 to 1.6 from the centre: all outside
        angle, radius = 2.399963 * i, 0.8 + 0.8 * ((i * 0.618034) % 1.0)
        points.InsertNextPoint(radius * math.cos(angle), radius * math.sin(angle), 0.0)
    probe.SetPoints(points)
    solver = flux_solver(probe, POINTS, seed=5)
    solver.SetBoundaryData(mesh)
    assert_solves_calibrated(solver, u)
    assert field(solver.GetOutput(), "OutsidePoints") == 0


def failing_solve(configure, level=3):
    solver = mixed_solver(box(level), cloud(4), walks=4)
    configure(solver, solver.GetInputDataObject(0, 0))
    catcher = MessageCatcher(solver)
    solver.Update()
    return catcher.error_text()


def test_messages_of_what_cannot_work():
    def bad_code(solver, mesh):
        mesh.GetCellData().GetArray("bc").SetValue(5, 4)
    assert ("may hold only 0 (Dirichlet), 1 (Neumann), 2 (Robin) and 3 (insulating sheet)"
            in failing_solve(bad_code))

    def no_condition_array(solver, mesh):
        solver.SetInputArrayToProcess(4, 0, 0, CELLS, "")
    assert "no Boundary Condition Array is chosen" in failing_solve(no_condition_array)

    def biharmonic(solver, mesh):
        solver.SetEquation(SOLVER.BIHARMONIC)
    assert "the biharmonic equation" in failing_solve(biharmonic)

    def robin_without_coefficients(solver, mesh):
        solver.SetInputArrayToProcess(6, 0, 0, CELLS, "None")
    assert "no Robin coefficient array" in failing_solve(robin_without_coefficients)

    def negative_coefficient(solver, mesh):
        mesh.GetCellData().GetArray("mu").Fill(-1.0)
    assert "must be finite and >= 0" in failing_solve(negative_coefficient)

    def all_neumann(solver, mesh):
        mesh.GetCellData().GetArray("bc").Fill(1)
    assert "no unique solution" in failing_solve(all_neumann)

    def flux_components(solver, mesh):
        add_point_array(mesh, "h3", lambda x, y, z: (0.0, 0.0, 0.0), components=3)
        solver.SetInputArrayToProcess(5, 0, 0, POINTS, "h3")
    assert "components" in failing_solve(flux_components)


def test_all_neumann_is_fine_when_screened():
    # Delta u - c u = f with u = cos(2 pi x), whose flux is 0 on every face
    # of the box: walks reflect everywhere, the source and the screening
    # alone make the value.
    c = 4.0
    mesh = box(level=4)
    mesh.GetCellData().GetArray("bc").Fill(1)
    solver = mixed_solver(mesh, cloud(200), walks=256)
    solver.SetEquation(SOLVER.SCREENED_POISSON)
    solver.SetScreeningCoefficient(c)
    pi = repr(math.pi)
    solver.SetSourceExpression(f"-(4*{pi}^2 + {c})*cos(2*{pi}*x)")
    solver.SetInputArrayToProcess(5, 0, 0, POINTS, "None")
    solver.SetInputArrayToProcess(6, 0, 0, CELLS, "None")
    catcher = MessageCatcher(solver)
    solver.Update()
    assert not catcher.errors, catcher.error_text()
    assert_calibrated(z_scores(solver.GetOutput(), lambda x, y, z: math.cos(2 * math.pi * x)))
