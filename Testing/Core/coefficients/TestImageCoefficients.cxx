// Tests of gridfree/coefficients/ImageCoefficients.h: the cubic B-spline's
// gradient and Laplacian are those of its values (finite differences), it
// reproduces linear data exactly, the Gaussian keeps constants and spreads
// an impulse by its width, and unusable arrays are refused with the array's
// name and the voxel.
#include <gridfree/coefficients/ImageCoefficients.h>

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

using namespace gridfree;

namespace
{
VoxelGrid Grid(int nx, int ny, int nz, double h)
{
  VoxelGrid g;
  g.Origin = { -0.3, 0.1, 0.2 };
  g.Spacing = { h, 1.5 * h, 0.8 * h };
  g.Dims = { nx, ny, nz };
  return g;
}

std::vector<double> Sampled(const VoxelGrid& g, double (*f)(double, double, double))
{
  std::vector<double> v;
  for (int k = 0; k < g.Dims[2]; ++k)
  {
    for (int j = 0; j < g.Dims[1]; ++j)
    {
      for (int i = 0; i < g.Dims[0]; ++i)
      {
        v.push_back(f(g.Origin[0] + i * g.Spacing[0], g.Origin[1] + j * g.Spacing[1],
          g.Origin[2] + k * g.Spacing[2]));
      }
    }
  }
  return v;
}

template <int DIM>
void ExpectDerivativesOfTheValues(const ImageCoefficients<DIM>& image, const Vec<DIM>& lo,
  const Vec<DIM>& hi)
{
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double e = 1e-4;
  for (int trial = 0; trial < 40; ++trial)
  {
    Vec<DIM> x;
    for (int i = 0; i < DIM; ++i)
    {
      x[i] = lo[i] + (hi[i] - lo[i]) * unit(rng);
    }
    CoefficientSample<DIM> c, plus, minus;
    image.Evaluate(x, c);
    double laplacian = 0.0;
    for (int i = 0; i < DIM; ++i)
    {
      Vec<DIM> d = Vec<DIM>::Zero();
      d[i] = e;
      image.Evaluate(x + d, plus);
      image.Evaluate(x - d, minus);
      EXPECT_NEAR(c.AlphaGradient[i], (plus.Alpha - minus.Alpha) / (2 * e), 1e-5);
      laplacian += (plus.Alpha - 2 * c.Alpha + minus.Alpha) / (e * e);
    }
    EXPECT_NEAR(c.AlphaLaplacian, laplacian, 2e-3 * (1.0 + std::abs(laplacian)));
  }
}

double Bumpy(double x, double y, double z)
{
  return 2.0 + std::sin(3 * x) * std::cos(2 * y) + 0.5 * std::sin(4 * z);
}
double Linear(double x, double y, double z) { return 2.0 + 0.3 * x - 0.2 * y + 0.1 * z; }
} // namespace

TEST(ImageCoefficients, GradientAndLaplacianAreTheSplines)
{
  const VoxelGrid g3 = Grid(20, 14, 18, 0.05);
  const ImageCoefficients<3> image3(g3, { Sampled(g3, Bumpy), 0.0 }, { {}, 1.0 }, { {}, 0.0 }, 0.0);
  ExpectDerivativesOfTheValues<3>(image3, Vec<3>(-0.2, 0.2, 0.3), Vec<3>(0.5, 1.0, 0.8));
  EXPECT_FALSE(image3.HasSource());
  const VoxelGrid g2 = Grid(30, 20, 1, 0.05);
  const ImageCoefficients<2> image2(g2, { Sampled(g2, Bumpy), 0.0 }, { {}, 0.0 }, { {}, 2.0 }, 0.07);
  ExpectDerivativesOfTheValues<2>(image2, Vec<2>(-0.2, 0.2), Vec<2>(1.0, 1.2));
  EXPECT_TRUE(image2.HasSource());
}

TEST(ImageCoefficients, ReproducesLinearData)
{
  const VoxelGrid g = Grid(12, 12, 12, 0.1);
  const ImageCoefficients<3> image(g, { Sampled(g, Linear), 0.0 }, { Sampled(g, Linear), 0.0 },
    { Sampled(g, Linear), 0.0 }, 0.0);
  const Vec<3> x(0.23, 0.61, 0.47);
  CoefficientSample<3> c;
  image.Evaluate(x, c);
  EXPECT_NEAR(c.Alpha, Linear(x[0], x[1], x[2]), 1e-12);
  EXPECT_NEAR(c.Absorption, Linear(x[0], x[1], x[2]), 1e-12);
  EXPECT_NEAR(c.Source, Linear(x[0], x[1], x[2]), 1e-12);
  EXPECT_NEAR(c.AlphaGradient[0], 0.3, 1e-12);
  EXPECT_NEAR(c.AlphaGradient[1], -0.2, 1e-12);
  EXPECT_NEAR(c.AlphaGradient[2], 0.1, 1e-12);
  EXPECT_NEAR(c.AlphaLaplacian, 0.0, 1e-10);
}

TEST(ImageCoefficients, GaussianKeepsConstantsAndSpreadsByItsWidth)
{
  VoxelGrid g = Grid(41, 1, 1, 0.1);
  std::vector<double> constant(41, 3.5);
  for (double v : SmoothOnGrid(g, constant, 0.25))
  {
    EXPECT_NEAR(v, 3.5, 1e-13);
  }
  std::vector<double> impulse(41, 0.0);
  impulse[20] = 1.0;
  const std::vector<double> spread = SmoothOnGrid(g, impulse, 0.3);
  double mass = 0.0, second = 0.0;
  for (int i = 0; i < 41; ++i)
  {
    const double d = (i - 20) * 0.1;
    mass += spread[i];
    second += spread[i] * d * d;
  }
  EXPECT_NEAR(mass, 1.0, 1e-13);
  EXPECT_NEAR(std::sqrt(second / mass), 0.3, 0.003);
}

TEST(ImageCoefficients, RefusesUnusableArrays)
{
  const VoxelGrid g = Grid(4, 3, 2, 0.1);
  std::vector<double> alpha(24, 1.0);
  alpha[4 * 3 + 5] = 0.0; // voxel (1, 1, 1)
  try
  {
    ImageCoefficients<3>(g, { alpha, 0.0 }, { {}, 0.0 }, { {}, 0.0 }, 0.0,
      { "Conductivity", "Perfusion", "Heat" });
    FAIL() << "no exception";
  }
  catch (const std::invalid_argument& e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("Conductivity must be positive"), std::string::npos) << message;
    EXPECT_NE(message.find("voxel (1, 1, 1)"), std::string::npos) << message;
  }
  std::vector<double> sigma(24, 0.5);
  sigma[3] = std::nan("");
  EXPECT_THROW(ImageCoefficients<3>(g, { {}, 1.0 }, { sigma, 0.0 }, { {}, 0.0 }, 0.0),
    std::invalid_argument);
  sigma[3] = -1.0;
  EXPECT_THROW(ImageCoefficients<3>(g, { {}, 1.0 }, { sigma, 0.0 }, { {}, 0.0 }, 0.0),
    std::invalid_argument);
  EXPECT_THROW(ImageCoefficients<3>(g, { std::vector<double>(23, 1.0), 0.0 }, { {}, 0.0 },
                 { {}, 0.0 }, 0.0),
    std::invalid_argument);
  EXPECT_THROW(ImageCoefficients<3>(g, { {}, -2.0 }, { {}, 0.0 }, { {}, 0.0 }, 0.0),
    std::invalid_argument);

  const ImageCoefficients<3> fine(g, { {}, 1.0 }, { {}, 0.0 }, { {}, 0.0 }, 0.0);
  EXPECT_TRUE(fine.Covers(Vec<3>(-0.3, 0.1, 0.2), Vec<3>(0.0, 0.4, 0.28)));
  EXPECT_FALSE(fine.Covers(Vec<3>(-0.3, 0.1, 0.2), Vec<3>(0.0, 0.4, 0.3)));
}

TEST(ImageCoefficients, SmoothingCountsItsVoxelsAndStopsWhenAsked)
{
  const VoxelGrid g = Grid(20, 10, 6, 0.1);
  std::vector<double> alpha(g.Count(), 1.0), sigma(g.Count(), 0.5);
  // Two arrays, three axes each: every voxel counted six times.
  PreparationMonitor monitor;
  ImageCoefficients<3>(g, { alpha, 0.0 }, { sigma, 0.0 }, { {}, 0.0 }, 0.15,
    { "alpha", "sigma", "f" }, &monitor);
  EXPECT_EQ(monitor.Total.load(), 6 * g.Count());
  EXPECT_EQ(monitor.Done.load(), monitor.Total.load());
  EXPECT_EQ(monitor.Fraction(), 1.0);
  // Asked to stop: it throws rather than leave a half-smoothed image.
  PreparationMonitor stopped;
  stopped.Stop = true;
  EXPECT_THROW(ImageCoefficients<3>(g, { alpha, 0.0 }, { sigma, 0.0 }, { {}, 0.0 }, 0.15,
                 { "alpha", "sigma", "f" }, &stopped),
    PreparationStopped);
  EXPECT_EQ(stopped.Done.load(), 0u);
}
