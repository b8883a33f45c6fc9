// The value, gradient and Hessian with mixed conditions (StarDerivativeWalks.h:
// the derivative estimator's first ball, then walk on stars) against closed
// forms on the walk-on-stars test shapes (MixedShapes.h: the U in 2D, the L
// prism in 3D, reflex corners on the Neumann part): Laplace with Neumann
// parts, Poisson, Robin, screened Poisson with Neumann conditions only.
// Every checked component within 5 standard errors at every point, mean z²
// in [0.7, 1.4]; a first ball that reaches past the Neumann part (its radius
// the distance to the Dirichlet part only) fails the same check.
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/stars/StarDerivativeWalks.h>

#include "EstimatorChecks.h"
#include "MixedShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

// A named namespace: the file may share a unity batch with the
// walk-on-stars tests, whose file-local names are the same.
namespace star_derivative_tests
{
using namespace gridfree;
using namespace gridfree::testing;

template <int DIM>
using HessianField = std::function<Mat<DIM>(const Vec<DIM>&)>;

// A closed form with its derivatives.
template <int DIM>
struct Exact
{
  Field<DIM> U;
  Gradient<DIM> Grad;
  HessianField<DIM> Hess;
};

// 2D: u = e^x sin y + x y + x/2 + 1 (the walk-on-stars tests' solution).
Exact<2> Harmonic2()
{
  Exact<2> e;
  e.U = [](const Vec2& x) { return std::exp(x[0]) * std::sin(x[1]) + x[0] * x[1] + 0.5 * x[0] + 1.0; };
  e.Grad = [](const Vec2& x) {
    return Vec2(std::exp(x[0]) * std::sin(x[1]) + x[1] + 0.5, std::exp(x[0]) * std::cos(x[1]) + x[0]);
  };
  e.Hess = [](const Vec2& x) {
    const double s = std::exp(x[0]) * std::sin(x[1]), c = std::exp(x[0]) * std::cos(x[1]);
    Mat<2> h;
    h << s, c + 1.0, c + 1.0, -s;
    return h;
  };
  return e;
}

// 3D: the L prism's u = e^{x/2} cos(0.3 y) sin(0.4 z) + x y − z.
Exact<3> Harmonic3()
{
  Exact<3> e;
  e.U = LPrismSolution;
  e.Grad = LPrismGradient;
  e.Hess = [](const Vec3& x) {
    const double ex = std::exp(0.5 * x[0]);
    const double cy = std::cos(0.3 * x[1]), sy = std::sin(0.3 * x[1]);
    const double cz = std::cos(0.4 * x[2]), sz = std::sin(0.4 * x[2]);
    Mat<3> h;
    h(0, 0) = 0.25 * ex * cy * sz;
    h(1, 1) = -0.09 * ex * cy * sz;
    h(2, 2) = -0.16 * ex * cy * sz;
    h(0, 1) = h(1, 0) = -0.15 * ex * sy * sz + 1.0;
    h(0, 2) = h(2, 0) = 0.2 * ex * cy * cz;
    h(1, 2) = h(2, 1) = -0.12 * ex * sy * cz;
    return h;
  };
  return e;
}

// Δu = 2n with u = |x|² + x₀.
template <int DIM>
Exact<DIM> Quadratic()
{
  Exact<DIM> e;
  e.U = [](const Vec<DIM>& x) { return x.squaredNorm() + x[0]; };
  e.Grad = [](const Vec<DIM>& x) {
    Vec<DIM> g = 2.0 * x;
    g[0] += 1.0;
    return g;
  };
  e.Hess = [](const Vec<DIM>&) { return Mat<DIM>(2.0 * Mat<DIM>::Identity()); };
  return e;
}

// Δu − c u = 0 with u = e^{√c a·x}.
template <int DIM>
Exact<DIM> Exponential(double c)
{
  Vec<DIM> a = Vec<DIM>::Ones();
  a[0] = -1.0;
  a.normalize();
  const double k = std::sqrt(c);
  Exact<DIM> e;
  e.U = [a, k](const Vec<DIM>& x) { return std::exp(k * a.dot(x)); };
  e.Grad = [a, k](const Vec<DIM>& x) { return Vec<DIM>(k * std::exp(k * a.dot(x)) * a); };
  e.Hess = [a, k](const Vec<DIM>& x) {
    return Mat<DIM>(k * k * std::exp(k * a.dot(x)) * a * a.transpose());
  };
  return e;
}

WalkSettings Settings(Equation equation = Equation::Laplace, double c = 0.0)
{
  WalkSettings s;
  s.Epsilon = 1e-4;
  s.Problem = equation;
  s.ScreeningCoefficient = c;
  return s;
}

template <int DIM>
std::vector<SlotCheck<DIM>> ChecksOf(const SampleLayout& layout, const Exact<DIM>& e, bool hessian)
{
  std::vector<SlotCheck<DIM>> checks;
  checks.push_back({ layout.Value, e.U });
  for (int i = 0; i < DIM; ++i)
  {
    checks.push_back({ layout.Gradient + i, [e, i](const Vec<DIM>& x) { return e.Grad(x)[i]; } });
  }
  for (int i = 0; hessian && i < DIM; ++i)
  {
    for (int j = i; j < DIM; ++j)
    {
      checks.push_back({ layout.Hessian + i * DIM + j,
        [e, i, j](const Vec<DIM>& x) { return e.Hess(x)(i, j); } });
    }
  }
  return checks;
}

// Runs the estimator at `points` and returns the calibration of the value,
// each gradient component and (with `hessian`) the Hessian's upper triangle.
template <int DIM, class Estimator = StarDerivativeWalks<DIM>>
std::vector<Calibration> Calibrations(const MixedBoundary<DIM>& boundary,
  const WalkSettings& settings, const Exact<DIM>& exact, const std::vector<Vec<DIM>>& points,
  int walks, bool hessian, VolumeSource<DIM>* volume = nullptr)
{
  DerivativeRequest request;
  request.Gradient = true;
  request.Hessian = hessian;
  const DerivativeRun run = RunDerivativeEstimator<DIM, Estimator>(
    boundary, settings, request, points, walks, 2027, volume);
  const SampleLayout layout = Estimator(boundary, settings, request, volume).Layout();
  return Calibrate<DIM>(run, points, ChecksOf<DIM>(layout, exact, hessian));
}

void ExpectAllCalibrated(const std::vector<Calibration>& calibrations, int points, const char* what)
{
  for (std::size_t k = 0; k < calibrations.size(); ++k)
  {
    std::printf("%s, check %zu: mean z² %.3f, max |z| %.2f\n", what, k, calibrations[k].MeanZ2,
      calibrations[k].MaxAbsZ);
    SCOPED_TRACE(std::string(what) + ", check " + std::to_string(k));
    ExpectCalibrated(calibrations[k], points);
  }
}

bool BottomSide2(const Vec2& c) { return c[1] < 1e-9; }
bool BottomOrBack3(const Vec3& c) { return LPrismDirichlet(c); }

TEST(StarDerivativeWalks, LaplaceMixed2D)
{
  const Shape<2> shape = UShape();
  const Exact<2> e = Harmonic2();
  const MixedBoundary<2> b = MakeMixed<2>(shape.Mesh, BottomSide2, e.U, e.Grad);
  ExpectAllCalibrated(
    Calibrations<2>(b, Settings(), e, PointsInside(shape, 300, 21), 1024, true), 300, "Laplace 2D");
}

TEST(StarDerivativeWalks, LaplaceMixed3D)
{
  const Shape<3> shape = LPrism();
  const Exact<3> e = Harmonic3();
  const MixedBoundary<3> b = MakeMixed<3>(shape.Mesh, BottomOrBack3, e.U, e.Grad);
  ExpectAllCalibrated(
    Calibrations<3>(b, Settings(), e, PointsInside(shape, 200, 22), 256, true), 200, "Laplace 3D");
}

TEST(StarDerivativeWalks, PoissonMixed3D)
{
  const Shape<3> shape = LPrism();
  const Exact<3> e = Quadratic<3>();
  const MixedBoundary<3> b = MakeMixed<3>(shape.Mesh, BottomOrBack3, e.U, e.Grad);
  FunctionSource<3> f([](const Vec3&) { return 6.0; });
  ExpectAllCalibrated(Calibrations<3>(b, Settings(Equation::Poisson), e,
                        PointsInside(shape, 200, 23), 256, true, &f),
    200, "Poisson 3D");
}

TEST(StarDerivativeWalks, RobinMixed3D)
{
  const Shape<3> shape = LPrism();
  const Exact<3> e = Harmonic3();
  const MixedBoundary<3> b = MakeMixed<3>(shape.Mesh, BottomOrBack3, e.U, e.Grad, true, 1.0,
    [](const Vec3& c) { return c[2] > 0.59 ? 1.5 : 0.0; });
  ASSERT_TRUE(b.HasRobin());
  ExpectAllCalibrated(
    Calibrations<3>(b, Settings(), e, PointsInside(shape, 200, 24), 256, false), 200, "Robin 3D");
}

TEST(StarDerivativeWalks, ScreenedPureNeumann3D)
{
  const Shape<3> shape = LPrism();
  const Exact<3> e = Exponential<3>(4.0);
  const MixedBoundary<3> b =
    MakeMixed<3>(shape.Mesh, [](const Vec3&) { return false; }, e.U, e.Grad);
  ASSERT_FALSE(b.HasDirichlet());
  ExpectAllCalibrated(Calibrations<3>(b, Settings(Equation::ScreenedPoisson, 4.0), e,
                        PointsInside(shape, 200, 25), 256, true),
    200, "screened Neumann 3D");
}

// A first ball whose radius is the distance to the Dirichlet part alone
// reaches past the Neumann part, where u is not the solution's continuation:
// the identities of the ball fail there.
template <int DIM>
class DirichletOnlyBall : public StarWalkContinuation<DIM>
{
public:
  DirichletOnlyBall(const MixedBoundary<DIM>& boundary, const WalkSettings& settings,
    VolumeSource<DIM>* volume, const ConcentratedSourceSet<DIM>& concentrated)
    : StarWalkContinuation<DIM>(boundary, settings, volume, concentrated)
    , Part(boundary.Dirichlet())
  {
  }
  double Distance(const Vec<DIM>& x) const { return this->Part.Distance(x); }

private:
  const Boundary<DIM>& Part;
};

TEST(StarDerivativeWalks, ABallPastTheNeumannPartFails)
{
  const Shape<3> shape = LPrism();
  const Exact<3> e = Harmonic3();
  const MixedBoundary<3> b = MakeMixed<3>(shape.Mesh, BottomOrBack3, e.U, e.Grad);
  const auto wrong = Calibrations<3, DerivativeWalkOnSpheres<3, DirichletOnlyBall<3>>>(
    b, Settings(), e, PointsInside(shape, 200, 22), 256, false);
  bool failed = false;
  for (std::size_t k = 1; k < wrong.size(); ++k)
  {
    std::printf("ball past the Neumann part, gradient %zu: mean z² %.3f, max |z| %.2f\n", k - 1,
      wrong[k].MeanZ2, wrong[k].MaxAbsZ);
    failed = failed || wrong[k].MeanZ2 > 2.0 || wrong[k].MaxAbsZ > 5.0;
  }
  EXPECT_TRUE(failed);
}
} // namespace star_derivative_tests
