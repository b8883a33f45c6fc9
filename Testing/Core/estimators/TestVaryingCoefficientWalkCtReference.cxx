// The varying-coefficient walk on real tissue coefficients against a
// reference solve written here: a 24 mm box inside the headsq CT (about
// half brain, half skull bone), the steady Pennes bioheat
// equation with the tissue table of Documentation/Examples/bioheat_tissues.py,
// coefficients smoothed by a 2 mm Gaussian and the cubic B-spline
// (ImageCoefficients.h). The reference is a conservative 7-point finite
// difference solve of the same smoothed coefficients (Eigen's conjugate
// gradients) at h = 0.5 mm and 1 mm, Richardson-extrapolated; the walk's
// values must lie within 5 standard errors of it at every probe point, with
// mean z² in [0.7, 1.4]. The same finite differences with the sharp,
// voxel-wise coefficients give the modelling error of the smoothing, which
// the test prints (Documentation/VaryingCoefficients.md quotes it).
#include <gridfree/coefficients/ImageCoefficients.h>
#include <gridfree/estimators/VaryingCoefficientWalk.h>
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// The tissue table per mm² (bioheat_tissues.py): α = k, σ = w·1e-6,
// f = −Q·1e-6 for skin (and the outside, which takes the skin's), fat, soft
// tissue (the box lies deeper than 10 mm inside the head, where soft tissue
// is brain) and bone; w = rate·1e-6/60 · density · 1049.75 · 3617.
struct Tissue
{
  double Alpha, Sigma, F;
};
double PerfusionOf(double mlPerMinPerKg, double density)
{
  return mlPerMinPerKg * 1e-6 / 60.0 * density * 1049.75 * 3617.0;
}
Tissue TissueOf(double ct)
{
  if (ct < 834.0)
  {
    return { 0.372, PerfusionOf(106.4, 1109.0) * 1e-6, 0.0 };
  }
  if (ct < 994.0)
  {
    return { 0.211, PerfusionOf(32.71, 911.0) * 1e-6, -0.507 * 911.0 * 1e-6 };
  }
  if (ct <= 1174.0)
  {
    return { 0.513, PerfusionOf(558.6, 1045.5) * 1e-6, -11.37 * 1045.5 * 1e-6 };
  }
  return { 0.40, 3400.0e-6, 0.0 };
}

struct HeadCt
{
  VoxelGrid Grid;
  std::vector<double> Values;

  // The sharp coefficients: the voxel nearest to x.
  Tissue NearestTissue(const Vec<3>& x) const
  {
    std::size_t index = 0, stride = 1;
    for (int a = 0; a < 3; ++a)
    {
      const long i = std::lround((x[a] - this->Grid.Origin[a]) / this->Grid.Spacing[a]);
      index += stride * static_cast<std::size_t>(std::min<long>(std::max<long>(i, 0), this->Grid.Dims[a] - 1));
      stride *= static_cast<std::size_t>(this->Grid.Dims[a]);
    }
    return TissueOf(this->Values[index]);
  }
};

HeadCt ReadHeadCt()
{
  HeadCt ct;
  ct.Grid.Origin = { 0.0, 0.0, 0.0 };
  ct.Grid.Spacing = { 3.2, 3.2, 1.5 };
  ct.Grid.Dims = { 64, 64, 93 };
  std::ifstream in(std::string(GRIDFREE_TEST_DATA_DIR) + "/headsq_headCT.raw", std::ios::binary);
  std::vector<std::int16_t> raw(ct.Grid.Count());
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size() * 2));
  EXPECT_TRUE(in.good()) << "cannot read Data/headsq_headCT.raw";
  ct.Values.assign(raw.begin(), raw.end());
  return ct;
}

// u on the nodes of a cube [lo, lo + side]³ with spacing h.
struct GridSolution
{
  Vec<3> Lo;
  double H = 0.0;
  int N = 0; // nodes per axis
  std::vector<double> U;

  double At(const Vec<3>& x) const
  {
    std::size_t index = 0, stride = 1;
    for (int a = 0; a < 3; ++a)
    {
      index += stride * static_cast<std::size_t>(std::lround((x[a] - this->Lo[a]) / this->H));
      stride *= static_cast<std::size_t>(this->N);
    }
    return this->U[index];
  }
};

// −∇·(α∇u) + σu = −f with u = g on the faces: conservative 7 points, α of
// each face from faceAlpha(a, b), σ and f at the nodes from tissueAt.
template <class FaceAlpha, class TissueAt, class Boundary>
GridSolution SolveFiniteDifferences(const Vec<3>& lo, double side, double h,
  FaceAlpha&& faceAlpha, TissueAt&& tissueAt, Boundary&& g)
{
  GridSolution s;
  s.Lo = lo;
  s.H = h;
  s.N = static_cast<int>(std::lround(side / h)) + 1;
  const int n = s.N, m = n - 2;
  auto node = [&](int i, int j, int k) { return Vec<3>(lo[0] + i * h, lo[1] + j * h, lo[2] + k * h); };
  auto unknown = [&](int i, int j, int k) { return (i - 1) + m * ((j - 1) + m * (k - 1)); };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m * m * m);
  const int offsets[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
    { 0, 0, -1 } };
  for (int k = 1; k <= m; ++k)
  {
    for (int j = 1; j <= m; ++j)
    {
      for (int i = 1; i <= m; ++i)
      {
        const int row = unknown(i, j, k);
        const Vec<3> x = node(i, j, k);
        const Tissue t = tissueAt(x);
        double diagonal = t.Sigma;
        b[row] -= t.F;
        for (const auto& o : offsets)
        {
          const int a = i + o[0], bb = j + o[1], c = k + o[2];
          const Vec<3> y = node(a, bb, c);
          const double weight = faceAlpha(x, y) / (h * h);
          diagonal += weight;
          if (a == 0 || a == n - 1 || bb == 0 || bb == n - 1 || c == 0 || c == n - 1)
          {
            b[row] += weight * g(y);
          }
          else
          {
            entries.emplace_back(row, unknown(a, bb, c), -weight);
          }
        }
        entries.emplace_back(row, row, diagonal);
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(m * m * m, m * m * m);
  matrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
    Eigen::IncompleteCholesky<double>>
    cg;
  cg.setTolerance(1e-11);
  cg.setMaxIterations(5000);
  cg.compute(matrix);
  const Eigen::VectorXd interior = cg.solve(b);
  EXPECT_EQ(cg.info(), Eigen::Success);
  s.U.assign(static_cast<std::size_t>(n) * n * n, 0.0);
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const bool face = i == 0 || i == n - 1 || j == 0 || j == n - 1 || k == 0 || k == n - 1;
        s.U[i + n * (j + n * k)] = face ? g(node(i, j, k)) : interior[unknown(i, j, k)];
      }
    }
  }
  return s;
}
} // namespace

TEST(VaryingCoefficientWalk, AgreesWithFiniteDifferencesOnTheHeadCt)
{
  const HeadCt ct = ReadHeadCt();
  std::vector<double> alpha, sigma, f;
  for (double v : ct.Values)
  {
    const Tissue t = TissueOf(v);
    alpha.push_back(t.Alpha);
    sigma.push_back(t.Sigma);
    f.push_back(t.F);
  }
  using Coefficient = ImageCoefficients<3>::Coefficient;
  const ImageCoefficients<3> smoothed(
    ct.Grid, Coefficient{ alpha, 0.0 }, Coefficient{ sigma, 0.0 }, Coefficient{ f, 0.0 }, 2.0);

  // The box: 24 mm about (102, 78, 62) mm; skin held at 34 °C against the
  // arterial 37 °C, with a gentle gradient across the box.
  const Vec<3> center(102.0, 78.0, 62.0);
  const double side = 24.0;
  const Vec<3> lo = center - Vec<3>::Constant(0.5 * side);
  auto g = [&](const Vec<3>& x) { return -3.0 + 0.05 * (x[0] - center[0]); };
  auto smoothTissue = [&](const Vec<3>& x) {
    CoefficientSample<3> c;
    smoothed.Evaluate(x, c);
    return Tissue{ c.Alpha, c.Absorption, c.Source };
  };
  auto smoothFace = [&](const Vec<3>& a, const Vec<3>& b) {
    CoefficientSample<3> c;
    smoothed.Evaluate(0.5 * (a + b), c);
    return c.Alpha;
  };
  const GridSolution fine = SolveFiniteDifferences(lo, side, 0.5, smoothFace, smoothTissue, g);
  const GridSolution coarse = SolveFiniteDifferences(lo, side, 1.0, smoothFace, smoothTissue, g);
  auto sharpTissue = [&](const Vec<3>& x) { return ct.NearestTissue(x); };
  auto sharpFace = [&](const Vec<3>& a, const Vec<3>& b) {
    const double alphaA = ct.NearestTissue(a).Alpha, alphaB = ct.NearestTissue(b).Alpha;
    return 2.0 * alphaA * alphaB / (alphaA + alphaB);
  };
  const GridSolution sharp = SolveFiniteDifferences(lo, side, 0.5, sharpFace, sharpTissue, g);

  // Probe points: nodes of the 1 mm grid at least 2 mm inside the box.
  std::mt19937 rng(29);
  std::uniform_int_distribution<int> node(2, coarse.N - 3);
  std::vector<Vec<3>> points;
  for (int p = 0; p < 160; ++p)
  {
    points.push_back(lo + Vec<3>(node(rng), node(rng), node(rng)));
  }

  SimplexMesh<3> cube = MakeCube(12, 0.5 * side);
  for (Vec<3>& v : cube.Vertices)
  {
    v += center;
  }
  Boundary<3> boundary;
  boundary.SetMesh(cube.Vertices, cube.Simplices,
    std::make_shared<CallableBoundaryValues<3>>(
      [&](const Vec<3>& p, std::int64_t, double* out) { *out = g(p); }, 1));
  const ScreeningBoundGrid<3> majorant(
    smoothed, boundary.BoundsMin(), boundary.BoundsMax(), ScreeningBoundGrid<3>::Settings());
  const VaryingCoefficientSettings settings;
  const DerivativeRun run = RunPointEstimator<3>(points, 1, 1024, 7, 2,
    [&]() { return VaryingCoefficientEstimator<3>(boundary, smoothed, majorant, settings); });

  double z2 = 0.0, maxZ = 0.0, largestFdError = 0.0, smallestSe = 1e300;
  double modelling2 = 0.0, largestModelling = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double h = fine.At(points[i]), twoH = coarse.At(points[i]);
    const double reference = (4.0 * h - twoH) / 3.0;
    const double se = std::sqrt(run.Variance[i]);
    const double z = (run.Mean[i] - reference) / se;
    z2 += z * z;
    maxZ = std::max(maxZ, std::abs(z));
    largestFdError = std::max(largestFdError, std::abs(h - twoH) / 3.0);
    smallestSe = std::min(smallestSe, se);
    const double modelling = sharp.At(points[i]) - reference;
    modelling2 += modelling * modelling;
    largestModelling = std::max(largestModelling, std::abs(modelling));
  }
  z2 /= static_cast<double>(points.size());
  std::printf("walk against the reference: mean z² %.3f, max |z| %.2f; finite differences' "
              "error (|u_h − u_2h|/3) at most %.2g °C, smallest standard error %.2g °C; "
              "smoothing's modelling error (sharp − smoothed): RMS %.3f °C, largest %.3f °C\n",
    z2, maxZ, largestFdError, smallestSe, std::sqrt(modelling2 / points.size()), largestModelling);
  EXPECT_LT(maxZ, 5.0);
  EXPECT_GT(z2, 0.7);
  EXPECT_LT(z2, 1.4);
  // The reference must be much more accurate than the walks' error bars.
  EXPECT_LT(largestFdError, 0.2 * smallestSe);
}
