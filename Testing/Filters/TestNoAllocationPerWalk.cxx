// Nothing allocates per walk in the core: every estimator, on every kind of
// boundary and source, runs its walks without touching the heap once its
// buffers exist (see AllocationCounter.h for how this is counted).
#include "AllocationCounter.h"
#include <gridfree/sources/ConcentratedSources.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include "EstimatorChecks.h"
#include <gridfree/geometry/BezierCurves.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/MeshSignedDistance.h>
#include <gridfree/implicit/SignedDistanceFunctions.h>
#include "TestMeshes.h"
#include <gridfree/estimators/WalkOnSpheres.h>

#include <gtest/gtest.h>

#include <memory>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
template <int DIM>
Boundary<DIM> SphereBoundary(int fields = 1)
{
  std::vector<Field<DIM>> f;
  for (int i = 0; i < fields; ++i)
  {
    f.push_back([i](const Vec<DIM>& x) { return x[0] + i * x[1]; });
  }
  return MakeBoundary<DIM>(UnitSphereMesh<DIM>(), f);
}

template <int DIM>
WalkSettings Settings(Equation equation)
{
  WalkSettings s;
  s.Epsilon = 1e-3;
  s.Problem = equation;
  s.ScreeningCoefficient = 2.0;
  return s;
}

template <int DIM>
void CheckPlainEstimators()
{
  const Boundary<DIM> boundary = SphereBoundary<DIM>();
  FunctionSource<DIM> source([](const Vec<DIM>& x) { return 1.0 + x.squaredNorm(); });
  for (Equation equation : { Equation::Laplace, Equation::Poisson, Equation::ScreenedPoisson })
  {
    for (SourceSampling sampling : { SourceSampling::Uniform, SourceSampling::MultipleImportance })
    {
      WalkSettings s = Settings<DIM>(equation);
      s.Sampling = sampling;
      WalkOnSpheresEstimator<DIM> estimator(boundary, s, &source);
      EXPECT_EQ(AllocationsOfWalks<DIM>(estimator, 1), 0)
        << "equation " << int(equation) << " sampling " << int(sampling);
    }
  }
  // Exterior walks (returns to the boundary sphere, or roulette).
  for (ExteriorStrategy strategy : { ExteriorStrategy::ExactReturn, ExteriorStrategy::RussianRoulette })
  {
    WalkSettings s = Settings<DIM>(Equation::Laplace);
    s.Exterior = strategy;
    WalkOnSpheresEstimator<DIM> estimator(boundary, s);
    EXPECT_EQ(AllocationsOfWalks<DIM>(estimator, 1, true), 0) << "exterior " << int(strategy);
  }
  // Biharmonic: g and h side by side; both strategies.
  const Boundary<DIM> two = SphereBoundary<DIM>(2);
  for (BiharmonicStrategy strategy : { BiharmonicStrategy::TreeWalking, BiharmonicStrategy::Nested })
  {
    WalkSettings s = Settings<DIM>(Equation::Biharmonic);
    s.Biharmonic = strategy;
    s.NestedWalks = 2;
    WalkOnSpheresEstimator<DIM> estimator(two, s);
    EXPECT_EQ(AllocationsOfWalks<DIM>(estimator, 2), 0) << "biharmonic " << int(strategy);
  }
}

template <int DIM>
void CheckConcentratedSources()
{
  const Boundary<DIM> boundary = SphereBoundary<DIM>();
  PointSources<DIM> points;
  std::vector<Vec<DIM>> positions = RandomPointsInBall<DIM>(50, 0.8, 9);
  points.Set(positions, 1, std::vector<double>(positions.size(), 1.0));
  CurveSources<DIM> curves;
  std::vector<Vec<DIM>> vertices = RandomPointsInBall<DIM>(40, 0.8, 10);
  std::vector<std::array<std::int64_t, 2>> segments;
  for (std::int64_t i = 0; i + 1 < static_cast<std::int64_t>(vertices.size()); ++i)
  {
    segments.push_back({ i, i + 1 });
  }
  curves.Set(vertices, segments, 1, std::vector<double>(vertices.size(), 2.0));
  ConcentratedSourceSet<DIM> set;
  set.Points = &points;
  set.Curves = &curves;
  for (Equation equation : { Equation::Poisson, Equation::ScreenedPoisson })
  {
    WalkOnSpheresEstimator<DIM> estimator(boundary, Settings<DIM>(equation), nullptr, set);
    EXPECT_EQ(AllocationsOfWalks<DIM>(estimator, 1), 0) << "equation " << int(equation);
  }
}

template <int DIM>
void CheckDerivativeEstimator()
{
  const Boundary<DIM> boundary = SphereBoundary<DIM>();
  FunctionSource<DIM> source([](const Vec<DIM>& x) { return 1.0 + x[0]; });
  DerivativeRequest request;
  request.Gradient = true;
  request.Hessian = true;
  request.ControlVariates = true;
  request.Directional = true;
  for (Equation equation : { Equation::Laplace, Equation::Poisson, Equation::ScreenedPoisson })
  {
    DerivativeWalkOnSpheres<DIM> estimator(boundary, Settings<DIM>(equation), request, &source);
    EXPECT_EQ(AllocationsOfWalks<DIM>(estimator, estimator.Layout().Size), 0)
      << "equation " << int(equation);
  }
}
} // namespace

TEST(NoAllocationPerWalk, PlainEstimators2D)
{
  CheckPlainEstimators<2>();
}

TEST(NoAllocationPerWalk, PlainEstimators3D)
{
  CheckPlainEstimators<3>();
}

TEST(NoAllocationPerWalk, ConcentratedSources2D)
{
  CheckConcentratedSources<2>();
}

TEST(NoAllocationPerWalk, ConcentratedSources3D)
{
  CheckConcentratedSources<3>();
}

TEST(NoAllocationPerWalk, DerivativeEstimator2D)
{
  CheckDerivativeEstimator<2>();
}

TEST(NoAllocationPerWalk, DerivativeEstimator3D)
{
  CheckDerivativeEstimator<3>();
}

// Implicit and CSG boundaries (a sphere minus a box, minus a closed mesh):
// distance and closest-point queries through the function tree.
TEST(NoAllocationPerWalk, ImplicitAndCsgBoundary)
{
  using Pointer = std::shared_ptr<const SignedDistanceFunction<3>>;
  const Pointer sphere = std::make_shared<SphereDistance<3>>(Vec3::Zero(), 1.0);
  const Pointer box = std::make_shared<BoxDistance<3>>(Vec3(0.9, 0.0, 0.0), Vec3(0.2, 0.2, 0.2));
  const SimplexMesh<3> small = MakeIcosphere(2, 0.15, Vec3(0.0, 0.8, 0.0));
  const Pointer mesh = std::make_shared<MeshSignedDistance<3>>(small.Vertices, small.Simplices);
  const Pointer hard = std::make_shared<CsgDistance<3>>(CsgOperation::Difference, sphere, box);
  const Pointer both = std::make_shared<CsgDistance<3>>(CsgOperation::Difference, hard, mesh, 0.05);
  const auto values = std::make_shared<CallableBoundaryValues<3>>(
    [](const Vec3& p, std::int64_t, double* out) { out[0] = p[0]; }, 1);
  Boundary<3> boundary;
  boundary.SetGeometry(std::make_shared<ImplicitBoundaryGeometry<3>>(both), values);
  WalkOnSpheresEstimator<3> plain(boundary, Settings<3>(Equation::Laplace));
  EXPECT_EQ(AllocationsOfWalks<3>(plain, 1), 0);
  DerivativeRequest request;
  request.Gradient = true;
  DerivativeWalkOnSpheres<3> derivative(boundary, Settings<3>(Equation::Laplace), request);
  EXPECT_EQ(AllocationsOfWalks<3>(derivative, derivative.Layout().Size), 0);
}

// Cubic Bézier boundaries (2D): the circle as four arcs.
TEST(NoAllocationPerWalk, BezierBoundary)
{
  const double k = 0.5522847498; // handle length of a quarter circle
  std::vector<CubicBezier> curves(4);
  const Vec2 axes[4] = { Vec2(1, 0), Vec2(0, 1), Vec2(-1, 0), Vec2(0, -1) };
  for (int i = 0; i < 4; ++i)
  {
    const Vec2 a = axes[i], b = axes[(i + 1) % 4];
    curves[i].P[0] = a;
    curves[i].P[1] = a + k * b;
    curves[i].P[2] = b + k * a;
    curves[i].P[3] = b;
  }
  const auto values = std::make_shared<CallableBoundaryValues<2>>(
    [](const Vec2& p, std::int64_t, double* out) { out[0] = p[0] * p[1]; }, 1);
  Boundary<2> boundary;
  boundary.SetGeometry(std::make_shared<BezierBoundaryGeometry>(curves), values);
  WalkOnSpheresEstimator<2> estimator(boundary, Settings<2>(Equation::Laplace));
  EXPECT_EQ(AllocationsOfWalks<2>(estimator, 1), 0);
}

// The counter itself works: a vector's growth is seen.
TEST(NoAllocationPerWalk, CounterSeesAllocations)
{
  AllocationCounter counter;
  std::vector<double>* v = new std::vector<double>(100);
  const long seen = counter.Stop();
  delete v;
  EXPECT_EQ(seen, 2);
}
