// Statistical tests of the gradient and Hessian estimators with control
// variates (paper Secs. 3, 4.1; FORMULAS.md §4–§5; DerivativeWalkOnSpheres.h)
// against closed forms in 2D and 3D, for the Laplace, Poisson, screened
// Poisson and biharmonic equations and for point sources: every component of
// the value, gradient and Hessian within 5 standard errors at every point and
// calibrated (mean z² in [0.7, 1.4]). Also: control variates reduce the
// variance; derived quantities; points on or next to the boundary; the same
// numbers whatever the thread count and however the walks are split.
#include "EstimatorChecks.h"
#include "TestSolutions.h"

#include <gtest/gtest.h>

#include <functional>
#include <iostream>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
constexpr int Points = 400;

template <int DIM>
WalkSettings Settings(Equation equation, double c = 0.0)
{
  WalkSettings s;
  s.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  s.Problem = equation;
  s.ScreeningCoefficient = c;
  return s;
}

// u = e^x cos y + xy(z) + 2: harmonic in 2D and 3D, with an offset that the
// gradient's control variate removes.
template <int DIM>
Solution<DIM> Harmonic()
{
  Solution<DIM> s;
  s.U = [](const Vec<DIM>& x) {
    const double p = DIM == 3 ? x[0] * x[1] * x[2] : x[0] * x[1];
    return std::exp(x[0]) * std::cos(x[1]) + p + 2.0;
  };
  s.Gradient = [](const Vec<DIM>& x) {
    const double e = std::exp(x[0]);
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = e * std::cos(x[1]);
    g[1] = -e * std::sin(x[1]);
    if constexpr (DIM == 3)
    {
      g += Vec<DIM>(x[1] * x[2], x[0] * x[2], x[0] * x[1]);
    }
    else
    {
      g += Vec<DIM>(x[1], x[0]);
    }
    return g;
  };
  s.Hessian = [](const Vec<DIM>& x) {
    const double e = std::exp(x[0]);
    Mat<DIM> h = Mat<DIM>::Zero();
    h(0, 0) = e * std::cos(x[1]);
    h(1, 1) = -e * std::cos(x[1]);
    h(0, 1) = h(1, 0) = -e * std::sin(x[1]);
    if constexpr (DIM == 3)
    {
      h(0, 1) += x[2];
      h(1, 0) += x[2];
      h(0, 2) = h(2, 0) = x[1];
      h(1, 2) = h(2, 1) = x[0];
    }
    else
    {
      h(0, 1) += 1.0;
      h(1, 0) += 1.0;
    }
    return h;
  };
  return s;
}

template <int DIM>
Solution<DIM> Smooth()
{
  return SmoothSolution<DIM>();
}

// u = |x|² v + xy with v = e^x cos y harmonic: Δ²u = 0, Δu = 2n v + 4 x·∇v.
template <int DIM>
Solution<DIM> Biharmonic()
{
  auto vOnly = [](const Vec<DIM>& x) { return std::exp(x[0]) * std::cos(x[1]); };
  auto vGrad = [](const Vec<DIM>& x) {
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = std::exp(x[0]) * std::cos(x[1]);
    g[1] = -std::exp(x[0]) * std::sin(x[1]);
    return g;
  };
  auto vHess = [](const Vec<DIM>& x) {
    const double e = std::exp(x[0]);
    Mat<DIM> h = Mat<DIM>::Zero();
    h(0, 0) = e * std::cos(x[1]);
    h(1, 1) = -e * std::cos(x[1]);
    h(0, 1) = h(1, 0) = -e * std::sin(x[1]);
    return h;
  };
  Solution<DIM> s;
  s.U = [=](const Vec<DIM>& x) { return x.squaredNorm() * vOnly(x) + x[0] * x[1]; };
  s.Gradient = [=](const Vec<DIM>& x) {
    Vec<DIM> g = 2.0 * x * vOnly(x) + x.squaredNorm() * vGrad(x);
    g[0] += x[1];
    g[1] += x[0];
    return g;
  };
  s.Hessian = [=](const Vec<DIM>& x) {
    Mat<DIM> h = 2.0 * vOnly(x) * Mat<DIM>::Identity() + 2.0 * x * vGrad(x).transpose() +
      2.0 * vGrad(x) * x.transpose() + x.squaredNorm() * vHess(x);
    h(0, 1) += 1.0;
    h(1, 0) += 1.0;
    return h;
  };
  return s;
}

template <int DIM>
double BiharmonicLaplacian(const Vec<DIM>& x)
{
  const double e = std::exp(x[0]);
  const double v = e * std::cos(x[1]);
  const double xGradV = x[0] * e * std::cos(x[1]) - x[1] * e * std::sin(x[1]);
  return 2.0 * DIM * v + 4.0 * xGradV;
}

// Checks of value, every gradient component and the upper triangle of the
// Hessian of solution component `component`.
template <int DIM>
std::vector<SlotCheck<DIM>> ChecksFor(
  const SampleLayout& layout, const Solution<DIM>& s, bool hessian, int component = 0)
{
  std::vector<SlotCheck<DIM>> checks;
  checks.push_back({ layout.Value + component, s.U });
  for (int i = 0; i < DIM; ++i)
  {
    checks.push_back(
      { layout.Gradient + component * DIM + i, [s, i](const Vec<DIM>& x) { return s.Gradient(x)[i]; } });
  }
  if (hessian)
  {
    for (int i = 0; i < DIM; ++i)
    {
      for (int j = i; j < DIM; ++j)
      {
        checks.push_back({ layout.Hessian + (component * DIM + i) * DIM + j,
          [s, i, j](const Vec<DIM>& x) { return s.Hessian(x)(i, j); } });
      }
    }
  }
  return checks;
}

void ExpectAllCalibrated(const std::vector<Calibration>& calibrations, const char* what)
{
  for (std::size_t k = 0; k < calibrations.size(); ++k)
  {
    SCOPED_TRACE(std::string(what) + ", check " + std::to_string(k));
    ExpectCalibrated(calibrations[k], Points);
  }
}

template <int DIM>
void CheckLaplace(bool controls, bool pairs = false)
{
  const Solution<DIM> s = Harmonic<DIM>();
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { s.U });
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  request.ControlVariates = controls;
  request.AntitheticPairs = pairs;
  const auto points = RandomPointsInBall<DIM>(Points, 0.85, 40 + DIM);
  const auto run =
    RunDerivativeEstimator<DIM>(boundary, Settings<DIM>(Equation::Laplace), request, points, 256, 7);
  const SampleLayout layout =
    DerivativeWalkOnSpheres<DIM>(boundary, Settings<DIM>(Equation::Laplace), request).Layout();
  ExpectAllCalibrated(Calibrate<DIM>(run, points, ChecksFor<DIM>(layout, s, true)),
    pairs ? "Laplace with antithetic pairs"
          : (controls ? "Laplace with control variates" : "Laplace without control variates"));
}

template <int DIM>
void CheckWithSource(Equation equation, double c, bool pairs = false)
{
  const Solution<DIM> s = Smooth<DIM>();
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { s.U });
  FunctionSource<DIM> f([s, c](const Vec<DIM>& x) { return s.Hessian(x).trace() - c * s.U(x); });
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  request.AntitheticPairs = pairs;
  const auto points = RandomPointsInBall<DIM>(Points, 0.85, 50 + DIM);
  const WalkSettings settings = Settings<DIM>(equation, c);
  const auto run = RunDerivativeEstimator<DIM>(boundary, settings, request, points, 256, 11, &f);
  const SampleLayout layout = DerivativeWalkOnSpheres<DIM>(boundary, settings, request, &f).Layout();
  ExpectAllCalibrated(Calibrate<DIM>(run, points, ChecksFor<DIM>(layout, s, true)),
    equation == Equation::Poisson ? "Poisson" : "screened Poisson");
}

template <int DIM>
void CheckBiharmonic(BiharmonicStrategy strategy)
{
  const Solution<DIM> s = Biharmonic<DIM>();
  const Boundary<DIM> boundary = MakeBoundary<DIM>(
    UnitSphereMesh<DIM>(), { s.U, [](const Vec<DIM>& x) { return BiharmonicLaplacian<DIM>(x); } });
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  WalkSettings settings = Settings<DIM>(Equation::Biharmonic);
  settings.Biharmonic = strategy;
  const auto points = RandomPointsInBall<DIM>(Points, 0.85, 60 + DIM);
  // 512 walks: the tree-walking samples are skewed (Σ R_k² is an exit
  // time), so fewer walks make the sample variance a poor guide at 5σ. The
  // nested samples are skewed too (each ball's inner walks end near the
  // boundary with a few far away): 1024 walks, as for curve sources in 3D.
  const int walks = strategy == BiharmonicStrategy::Nested ? 1024 : 512;
  const auto run = RunDerivativeEstimator<DIM>(boundary, settings, request, points, walks, 13);
  const SampleLayout layout = DerivativeWalkOnSpheres<DIM>(boundary, settings, request).Layout();
  auto checks = ChecksFor<DIM>(layout, s, true);
  checks.push_back({ layout.Laplacian, [](const Vec<DIM>& x) { return BiharmonicLaplacian<DIM>(x); } });
  ExpectAllCalibrated(Calibrate<DIM>(run, points, checks), "biharmonic");
}

// Free-space potential of point sources, Δu = Σ s_k δ_{z_k}, plus 1.
template <int DIM>
Solution<DIM> PointPotential(const std::vector<Vec<DIM>>& centres, const std::vector<double>& strength)
{
  Solution<DIM> s;
  s.U = [=](const Vec<DIM>& x) {
    double u = 1.0;
    for (std::size_t k = 0; k < centres.size(); ++k)
    {
      const double r = (x - centres[k]).norm();
      u += strength[k] * (DIM == 3 ? -1.0 / (4.0 * M_PI * r) : std::log(r) / (2.0 * M_PI));
    }
    return u;
  };
  s.Gradient = [=](const Vec<DIM>& x) {
    Vec<DIM> g = Vec<DIM>::Zero();
    for (std::size_t k = 0; k < centres.size(); ++k)
    {
      const Vec<DIM> d = x - centres[k];
      g += strength[k] * d / (UnitSphereArea<DIM>() * std::pow(d.norm(), DIM));
    }
    return g;
  };
  s.Hessian = [=](const Vec<DIM>& x) {
    Mat<DIM> h = Mat<DIM>::Zero();
    for (std::size_t k = 0; k < centres.size(); ++k)
    {
      const Vec<DIM> d = x - centres[k];
      const double r = d.norm();
      h += strength[k] *
        (Mat<DIM>::Identity() - DIM * d * d.transpose() / (r * r)) /
        (UnitSphereArea<DIM>() * std::pow(r, DIM));
    }
    return h;
  };
  return s;
}

template <int DIM>
void CheckPointSources()
{
  std::vector<Vec<DIM>> centres(2, Vec<DIM>::Zero());
  centres[0][0] = 0.3;
  centres[0][1] = 0.2;
  centres[1][0] = -0.35;
  centres[1][1] = -0.1;
  const std::vector<double> strength = { 1.5, -0.8 };
  const Solution<DIM> s = PointPotential<DIM>(centres, strength);
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { s.U });
  PointSources<DIM> sources;
  sources.Set(centres, 1, strength);
  ConcentratedSourceSet<DIM> set;
  set.Points = &sources;
  // Probe points at least 0.15 from every source.
  std::vector<Vec<DIM>> points;
  for (const Vec<DIM>& p : RandomPointsInBall<DIM>(3 * Points, 0.85, 70 + DIM))
  {
    if ((p - centres[0]).norm() > 0.15 && (p - centres[1]).norm() > 0.15 &&
      static_cast<int>(points.size()) < Points)
    {
      points.push_back(p);
    }
  }
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  const WalkSettings settings = Settings<DIM>(Equation::Poisson);
  const auto run =
    RunDerivativeEstimator<DIM>(boundary, settings, request, points, 256, 17, nullptr, set);
  const SampleLayout layout =
    DerivativeWalkOnSpheres<DIM>(boundary, settings, request, nullptr, set).Layout();
  ExpectAllCalibrated(Calibrate<DIM>(run, points, ChecksFor<DIM>(layout, s, true)), "point sources");
}
} // namespace

TEST(DerivativeWalkOnSpheres, Laplace2D) { CheckLaplace<2>(true); }
TEST(DerivativeWalkOnSpheres, Laplace3D) { CheckLaplace<3>(true); }
TEST(DerivativeWalkOnSpheres, LaplaceWithoutControlVariates2D) { CheckLaplace<2>(false); }
TEST(DerivativeWalkOnSpheres, LaplaceWithoutControlVariates3D) { CheckLaplace<3>(false); }
TEST(DerivativeWalkOnSpheres, LaplaceWithAntitheticPairs2D) { CheckLaplace<2>(true, true); }
TEST(DerivativeWalkOnSpheres, LaplaceWithAntitheticPairs3D) { CheckLaplace<3>(true, true); }
TEST(DerivativeWalkOnSpheres, ScreenedPoissonWithAntitheticPairs3D)
{
  CheckWithSource<3>(Equation::ScreenedPoisson, 4.0, true);
}
TEST(DerivativeWalkOnSpheres, Poisson2D) { CheckWithSource<2>(Equation::Poisson, 0.0); }
TEST(DerivativeWalkOnSpheres, Poisson3D) { CheckWithSource<3>(Equation::Poisson, 0.0); }
TEST(DerivativeWalkOnSpheres, ScreenedPoisson2D) { CheckWithSource<2>(Equation::ScreenedPoisson, 4.0); }
TEST(DerivativeWalkOnSpheres, ScreenedPoisson3D) { CheckWithSource<3>(Equation::ScreenedPoisson, 4.0); }
TEST(DerivativeWalkOnSpheres, Biharmonic2D) { CheckBiharmonic<2>(BiharmonicStrategy::TreeWalking); }
TEST(DerivativeWalkOnSpheres, Biharmonic3D) { CheckBiharmonic<3>(BiharmonicStrategy::TreeWalking); }
TEST(DerivativeWalkOnSpheres, BiharmonicNested2D) { CheckBiharmonic<2>(BiharmonicStrategy::Nested); }
TEST(DerivativeWalkOnSpheres, PointSources2D) { CheckPointSources<2>(); }
TEST(DerivativeWalkOnSpheres, PointSources3D) { CheckPointSources<3>(); }

// Control variates cut the variance of every derivative (Sec. 4.1, Fig. 15):
// the per-point variance of the mean, averaged, drops by the stated factors.
TEST(DerivativeWalkOnSpheres, ControlVariatesReduceVariance)
{
  const Solution<3> s = Harmonic<3>();
  const Boundary<3> boundary = MakeBoundary<3>(UnitSphereMesh<3>(), { s.U });
  const auto points = RandomPointsInBall<3>(100, 0.85, 80);
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  double variance[2][3] = { { 0, 0, 0 }, { 0, 0, 0 } };
  SampleLayout layout;
  for (int on = 0; on < 2; ++on)
  {
    request.ControlVariates = on == 1;
    layout = DerivativeWalkOnSpheres<3>(boundary, Settings<3>(Equation::Laplace), request).Layout();
    const auto run =
      RunDerivativeEstimator<3>(boundary, Settings<3>(Equation::Laplace), request, points, 256, 3);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      variance[on][0] += run.Variance[i * run.Size + layout.Value];
      for (int k = 0; k < 3; ++k)
      {
        variance[on][1] += run.Variance[i * run.Size + layout.Gradient + k];
      }
      for (int k = 0; k < 9; ++k)
      {
        variance[on][2] += run.Variance[i * run.Size + layout.Hessian + k];
      }
    }
  }
  std::cout << "variance ratio without/with control variates: value "
            << variance[0][0] / variance[1][0] << ", gradient " << variance[0][1] / variance[1][1]
            << ", Hessian " << variance[0][2] / variance[1][2] << "\n";
  EXPECT_GT(variance[0][0] / variance[1][0], 1.1) << "value";
  EXPECT_GT(variance[0][1] / variance[1][1], 9.0) << "gradient";
  EXPECT_GT(variance[0][2] / variance[1][2], 16.0) << "Hessian";
}

// A pair of walks whose second replays the first one's random numbers from
// the opposite point of the first sphere: at equal walk count its gradient
// has less variance than two walks with control variates (the even part of
// u on the sphere cancels), and its value no more.
TEST(DerivativeWalkOnSpheres, AntitheticPairsReduceGradientVariance)
{
  const Solution<3> s = Harmonic<3>();
  const Boundary<3> boundary = MakeBoundary<3>(UnitSphereMesh<3>(), { s.U });
  const auto points = RandomPointsInBall<3>(100, 0.85, 81);
  DerivativeRequest request;
  request.Gradient = true;
  double variance[2][2] = { { 0, 0 }, { 0, 0 } };
  for (int pairs = 0; pairs < 2; ++pairs)
  {
    request.AntitheticPairs = pairs == 1;
    const SampleLayout layout =
      DerivativeWalkOnSpheres<3>(boundary, Settings<3>(Equation::Laplace), request).Layout();
    // The same 512 walks per point: 512 samples, or 256 pairs.
    const auto run = RunDerivativeEstimator<3>(
      boundary, Settings<3>(Equation::Laplace), request, points, pairs ? 256 : 512, 5);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      variance[pairs][0] += run.Variance[i * run.Size + layout.Value];
      for (int k = 0; k < 3; ++k)
      {
        variance[pairs][1] += run.Variance[i * run.Size + layout.Gradient + k];
      }
    }
  }
  std::cout << "variance of the mean, two walks with control variates over one pair: value "
            << variance[0][0] / variance[1][0] << ", gradient " << variance[0][1] / variance[1][1]
            << "\n";
  EXPECT_GT(variance[0][1] / variance[1][1], 1.2) << "gradient";
  EXPECT_GT(variance[0][0] / variance[1][0], 0.8) << "value";
}

// Z·∇u, ∇·u and ∇×u of a 3-component solution, each with its own variance.
TEST(DerivativeWalkOnSpheres, DirectionalDerivativeDivergenceAndCurl)
{
  // Three harmonic components: u0 = e^x cos y, u1 = −e^x sin y + z,
  // u2 = xy + 2z.
  const Field<3> u0 = [](const Vec3& x) { return std::exp(x[0]) * std::cos(x[1]); };
  const Field<3> u1 = [](const Vec3& x) { return -std::exp(x[0]) * std::sin(x[1]) + x[2]; };
  const Field<3> u2 = [](const Vec3& x) { return x[0] * x[1] + 2.0 * x[2]; };
  const Boundary<3> boundary = MakeBoundary<3>(UnitSphereMesh<3>(), { u0, u1, u2 });
  DerivativeRequest request;
  request.Gradient = true;
  request.Directional = true;
  request.Direction = { 0.6, 0.0, 0.8 };
  request.DivergenceCurl = true;
  const auto points = RandomPointsInBall<3>(Points, 0.85, 90);
  const WalkSettings settings = Settings<3>(Equation::Laplace);
  const auto run = RunDerivativeEstimator<3>(boundary, settings, request, points, 256, 5);
  const SampleLayout layout = DerivativeWalkOnSpheres<3>(boundary, settings, request).Layout();
  ASSERT_GE(layout.Directional, 0);
  ASSERT_GE(layout.Divergence, 0);
  // J = ∂u_i/∂x_j: ∇·u = e^x cos y − e^x cos y + 2 = 2;
  // ∇×u = (∂u2/∂y − ∂u1/∂z, ∂u0/∂z − ∂u2/∂x, ∂u1/∂x − ∂u0/∂y) = (x − 1, −y, 0).
  std::vector<SlotCheck<3>> checks = {
    { layout.Directional + 0,
      [](const Vec3& x) { return 0.6 * std::exp(x[0]) * std::cos(x[1]); } },
    { layout.Directional + 1,
      [](const Vec3& x) { return 0.6 * -std::exp(x[0]) * std::sin(x[1]) + 0.8; } },
    { layout.Directional + 2, [](const Vec3& x) { return 0.6 * x[1] + 0.8 * 2.0; } },
    { layout.Divergence, [](const Vec3&) { return 2.0; } },
    { layout.Curl + 0, [](const Vec3& x) { return x[0] - 1.0; } },
    { layout.Curl + 1, [](const Vec3& x) { return -x[1]; } },
  };
  auto calibrations = Calibrate<3>(run, points, checks);
  ExpectAllCalibrated(calibrations, "derived quantities");
  // (∇×u)_z = ∂u1/∂x − ∂u0/∂y = 0: its estimate must be zero within 5 standard
  // errors.
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double mean = run.Mean[i * run.Size + layout.Curl + 2];
    EXPECT_LT(std::abs(mean), 5.0 * std::sqrt(run.Variance[i * run.Size + layout.Curl + 2]) + 1e-12);
  }
}

// A point within ε of the boundary, or on it, gets its value from the
// boundary and one-sided derivatives: flagged, finite, and close to exact.
TEST(DerivativeWalkOnSpheres, PointsOnAndNearTheBoundaryAreOneSided)
{
  const Solution<3> s = Harmonic<3>();
  const auto mesh = UnitSphereMesh<3>();
  const Boundary<3> boundary = MakeBoundary<3>(mesh, { s.U });
  const WalkSettings settings = Settings<3>(Equation::Laplace);
  std::vector<Vec3> points;
  // Mesh vertices (exactly on the boundary) and points ε/2 inside them.
  for (int k = 0; k < 20; ++k)
  {
    const Vec3 v = mesh.Vertices[k * 97];
    points.push_back(v);
    points.push_back(v * (1.0 - 0.5 * settings.Epsilon));
  }
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  const auto run = RunDerivativeEstimator<3>(boundary, settings, request, points, 1024, 21);
  const SampleLayout layout = DerivativeWalkOnSpheres<3>(boundary, settings, request).Layout();
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    EXPECT_EQ(run.Status[i], DerivativeStatus::OneSided);
    for (int c = 0; c < run.Size; ++c)
    {
      EXPECT_TRUE(std::isfinite(run.Mean[i * run.Size + c])) << "point " << i << " slot " << c;
    }
    EXPECT_NEAR(run.Mean[i * run.Size + layout.Value], s.U(points[i]), 1e-3);
    for (int k = 0; k < 3; ++k)
    {
      const double exact = s.Gradient(points[i])[k];
      const double mean = run.Mean[i * run.Size + layout.Gradient + k];
      const double sd = std::sqrt(run.Variance[i * run.Size + layout.Gradient + k]);
      EXPECT_LT(std::abs(mean - exact), 6.0 * sd + 0.05) << "point " << i << " component " << k;
    }
  }
}

// Walks split into calls at control-block boundaries, run in any order into
// recorders and replayed in walk order, or spread over a different number of
// threads, give bit-identical means: control variates only look at earlier
// walks of the same block (kControlBlock walks) of the same point.
// With antithetic pairs too: a pair's second walk replays the numbers of
// the sample's own stream, whatever thread or call runs it.
class DerivativeWalkOnSpheresPairs : public ::testing::TestWithParam<bool>
{
};

TEST_P(DerivativeWalkOnSpheresPairs, ReproducibleAcrossSplitsAndThreads)
{
  const Solution<2> s = Smooth<2>();
  const Boundary<2> boundary = MakeBoundary<2>(UnitSphereMesh<2>(), { s.U });
  FunctionSource<2> f([s](const Vec2& x) { return s.Hessian(x).trace(); });
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  request.AntitheticPairs = GetParam();
  const WalkSettings settings = Settings<2>(Equation::Poisson);
  const auto points = RandomPointsInBall<2>(40, 0.8, 99);
  constexpr int block = DerivativeWalkOnSpheres<2>::kControlBlock;
  const int walks = 2 * block + 10; // a short last block
  const auto one = RunDerivativeEstimator<2>(boundary, settings, request, points, walks, 1, &f,
    ConcentratedSourceSet<2>(), 1);
  const auto two = RunDerivativeEstimator<2>(boundary, settings, request, points, walks, 1, &f,
    ConcentratedSourceSet<2>(), 2);
  EXPECT_EQ(one.Mean, two.Mean);
  EXPECT_EQ(one.Variance, two.Variance);

  DerivativeWalkOnSpheres<2> estimator(boundary, settings, request, &f);
  const int size = estimator.Layout().Size;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double xyz[3] = { points[i][0], points[i][1], 0.0 };
    // Two calls split at a block boundary.
    RunningStatistics stats(size);
    WalkCounters counters;
    estimator.EstimatePoint(xyz, 1, 0, block, stats, counters);
    estimator.EstimatePoint(xyz, 1, block, walks - block, stats, counters);
    // The three blocks run last to first into recorders, replayed in order.
    SampleRecorder recorders[3] = { SampleRecorder(size), SampleRecorder(size),
      SampleRecorder(size) };
    for (int b = 2; b >= 0; --b)
    {
      estimator.EstimatePoint(
        xyz, 1, b * block, std::min(block, walks - b * block), recorders[b], counters);
    }
    RunningStatistics replayed(size);
    for (const SampleRecorder& r : recorders)
    {
      r.ReplayInto(replayed);
    }
    ASSERT_EQ(replayed.SampleCount(), static_cast<std::size_t>(walks));
    for (int c = 0; c < size; ++c)
    {
      EXPECT_EQ(stats.GetMean(c), one.Mean[i * size + c]);
      EXPECT_EQ(replayed.GetMean(c), one.Mean[i * size + c]);
      EXPECT_EQ(replayed.VarianceOfMean(c), stats.VarianceOfMean(c));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DerivativeWalkOnSpheres, DerivativeWalkOnSpheresPairs,
  ::testing::Values(false, true),
  [](const ::testing::TestParamInfo<bool>& info) { return info.param ? "AntitheticPairs" : "SingleWalks"; });

// Exterior problem (Sec. 2.6): u = 1/|x − p| outside the unit sphere (p inside),
// u → 0 at infinity. The first ball may be huge; the rest of the walk returns
// by the exact-return roulette.
TEST(DerivativeWalkOnSpheres, Exterior3D)
{
  const Vec3 p(0.2, -0.1, 0.15);
  Solution<3> s;
  s.U = [p](const Vec3& x) { return 1.0 / (x - p).norm(); };
  s.Gradient = [p](const Vec3& x) {
    const Vec3 d = x - p;
    return Vec3(-d / std::pow(d.norm(), 3));
  };
  s.Hessian = [p](const Vec3& x) {
    const Vec3 d = x - p;
    const double r = d.norm();
    return Mat<3>(3.0 * d * d.transpose() / std::pow(r, 5) - Mat<3>::Identity() / std::pow(r, 3));
  };
  const Boundary<3> boundary = MakeBoundary<3>(UnitSphereMesh<3>(), { s.U });
  const auto points = RandomPointsInBall<3>(Points, 3.0, 110, 1.2);
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  const WalkSettings settings = Settings<3>(Equation::Laplace);
  const auto run = RunDerivativeEstimator<3>(boundary, settings, request, points, 256, 23);
  const SampleLayout layout = DerivativeWalkOnSpheres<3>(boundary, settings, request).Layout();
  ExpectAllCalibrated(Calibrate<3>(run, points, ChecksFor<3>(layout, s, true)), "exterior");
}

// A screened ball far larger than the screening length (z = √c R beyond
// ~745) has C and κ both underflowing to 0: the value's control C b̄·ν,
// b̄ = (n/κ) ∇̄u, must then be 0, not 0 · inf = NaN. Points far outside the
// boundary make such balls; their solution is 0 to double precision.
TEST(DerivativeWalkOnSpheres, ScreenedBallsBeyondUnderflowGiveZeroNotNaN)
{
  const Boundary<3> boundary =
    MakeBoundary<3>(MakeIcosphere(2), { [](const Vec3& x) { return 1.0 + x[0]; } });
  WalkSettings settings;
  settings.Epsilon = 1e-3;
  settings.Problem = Equation::ScreenedPoisson;
  settings.ScreeningCoefficient = 1.0;
  DerivativeRequest request;
  request.Gradient = true;
  request.Hessian = true;
  request.ControlVariates = true;
  DerivativeWalkOnSpheres<3> estimator(boundary, settings, request);
  for (double distance : { 1e3, 1e5, 1e20 })
  {
    RunningStatistics stats(estimator.Layout().Size);
    WalkCounters counters;
    const double xyz[3] = { distance, 0.0, 0.0 };
    estimator.EstimatePoint(xyz, 3, 0, 600, stats, counters);
    for (int k = 0; k < estimator.Layout().Size; ++k)
    {
      EXPECT_EQ(stats.GetMean(k), 0.0) << "distance " << distance << " output " << k;
    }
  }
}
