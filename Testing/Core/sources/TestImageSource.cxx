// Tests of gridfree/sources/ImageSource.h: trilinear interpolation on a grid
// reproduces linear functions and their gradients exactly, with or without a
// rotated direction matrix, in 3D and in a 2D plane, for several components;
// zero outside the grid.
#include <gridfree/sources/ImageSource.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

using namespace gridfree;

namespace
{
// The grid point (i, j, k) in world coordinates: origin + R · (spacing ∘ index),
// with R the direction matrix (PhysicalToIndex is its inverse, Rᵀ).
Vec3 GridPoint(const ImageSource<3>::Shared& s, const double R[9], int i, int j, int k)
{
  const double local[3] = { i * s.Spacing[0], j * s.Spacing[1], k * s.Spacing[2] };
  Vec3 p;
  for (int r = 0; r < 3; ++r)
  {
    p[r] = s.Origin[r] + R[3 * r] * local[0] + R[3 * r + 1] * local[1] + R[3 * r + 2] * local[2];
  }
  return p;
}

// A grid of dims with values of two linear functions at its points.
std::shared_ptr<ImageSource<3>::Shared> LinearGrid(const double R[9], std::array<int, 3> dims)
{
  auto s = std::make_shared<ImageSource<3>::Shared>();
  s->Origin = { 1.0, -2.0, 0.5 };
  s->Spacing = { 0.5, 0.25, 1.0 };
  s->Dims = dims;
  s->Components = 2;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      s->PhysicalToIndex[3 * r + c] = R[3 * c + r]; // the inverse of a rotation
    }
  }
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const Vec3 p = GridPoint(*s, R, i, j, k);
        // Values in float: choose them exactly representable.
        s->Values.push_back(static_cast<float>(2 * i - 3 * j + k));
        s->Values.push_back(static_cast<float>(i + j + 4 * k));
        (void)p;
      }
    }
  }
  s->Min = Vec3::Constant(-1e9);
  s->Max = Vec3::Constant(1e9);
  return s;
}

void ExpectLinearReproduced(const double R[9])
{
  const auto shared = LinearGrid(R, { 5, 4, 3 });
  ImageSource<3> source(shared);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 200; ++n)
  {
    const double index[3] = { 4 * u(rng), 3 * u(rng), 2 * u(rng) };
    const double local[3] = { index[0] * 0.5, index[1] * 0.25, index[2] * 1.0 };
    Vec3 y;
    for (int r = 0; r < 3; ++r)
    {
      y[r] = shared->Origin[r] + R[3 * r] * local[0] + R[3 * r + 1] * local[1] +
        R[3 * r + 2] * local[2];
    }
    double f[2], g[6];
    source.EvaluateGradient(y, 2, f, g);
    EXPECT_NEAR(f[0], 2 * index[0] - 3 * index[1] + index[2], 1e-12);
    EXPECT_NEAR(f[1], index[0] + index[1] + 4 * index[2], 1e-12);
    double value[2];
    source.Evaluate(y, value);
    EXPECT_EQ(value[0], f[0]); // the same sums either way
    EXPECT_EQ(value[1], f[1]);
    // ∂f/∂y = Σ_k ∂f/∂index_k · ∂index_k/∂y, ∂index_k/∂y_j = R[j][k] / spacing_k.
    const double dIndex[2][3] = { { 2, -3, 1 }, { 1, 1, 4 } };
    const double spacing[3] = { 0.5, 0.25, 1.0 };
    for (int c = 0; c < 2; ++c)
    {
      for (int j = 0; j < 3; ++j)
      {
        double exact = 0.0;
        for (int k = 0; k < 3; ++k)
        {
          exact += dIndex[c][k] * R[3 * j + k] / spacing[k];
        }
        EXPECT_NEAR(g[3 * c + j], exact, 1e-11);
      }
    }
  }
  // Outside: zero, gradient zero.
  double f[2], g[6];
  const Vec3 outside(shared->Origin[0] - 5.0, shared->Origin[1] - 5.0, shared->Origin[2] - 5.0);
  source.EvaluateGradient(outside, 2, f, g);
  for (double v : f)
  {
    EXPECT_EQ(v, 0.0);
  }
  for (double v : g)
  {
    EXPECT_EQ(v, 0.0);
  }
}
} // namespace

TEST(ImageSource, ReproducesLinearFunctionsAndGradients)
{
  const double identity[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  ExpectLinearReproduced(identity);
}

TEST(ImageSource, HonoursARotatedDirectionMatrix)
{
  // 90° about z, then 90° about x: index axes point along y, z and x.
  const double rotation[9] = { 0, 0, 1, 1, 0, 0, 0, 1, 0 };
  ExpectLinearReproduced(rotation);
}

TEST(ImageSource, SingleSliceIsConstantAcrossItsPlaneIn2D)
{
  const double identity[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  auto shared3 = LinearGrid(identity, { 5, 4, 1 });
  auto shared = std::make_shared<ImageSource<2>::Shared>();
  shared->Origin = shared3->Origin;
  shared->Spacing = shared3->Spacing;
  shared->Dims = shared3->Dims;
  shared->PhysicalToIndex = shared3->PhysicalToIndex;
  shared->Components = 2;
  shared->Values = shared3->Values;
  shared->PlaneZ = 7.0; // far from the slice's z: a single sample is constant along z
  shared->Min = Vec2(1.0, -2.0);
  shared->Max = Vec2(3.0, -1.25);
  ImageSource<2> source(shared);
  double f[2], g[4];
  const Vec2 y(1.0 + 0.5 * 2.5, -2.0 + 0.25 * 1.5); // index (2.5, 1.5)
  source.EvaluateGradient(y, 2, f, g);
  EXPECT_NEAR(f[0], 2 * 2.5 - 3 * 1.5, 1e-12);
  EXPECT_NEAR(f[1], 2.5 + 1.5, 1e-12);
  EXPECT_NEAR(g[0], 2 / 0.5, 1e-12);
  EXPECT_NEAR(g[1], -3 / 0.25, 1e-12);
  EXPECT_NEAR(g[2], 1 / 0.5, 1e-12);
  EXPECT_NEAR(g[3], 1 / 0.25, 1e-12);
  Vec2 lo, hi;
  EXPECT_TRUE(source.SupportBounds(lo, hi));
  EXPECT_EQ(lo, shared->Min);
}
