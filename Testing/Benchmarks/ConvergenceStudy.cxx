// Convergence of the value, gradient and Hessian estimators with and without
// control variates, after Fig. 15 of Sawhney & Crane, "Monte Carlo Geometry
// Processing" (2020), on a 2D Poisson problem in the spirit of their Fig. 6.
//
// Domain: the non-convex flower r(θ) = 1 + 0.3 cos 5θ, a closed polygon of
// 4096 segments. Solution: u = e^{a·y} sin(b·y) + x²y + 1 (TestSolutions.h,
// SmoothSolution<2>), not harmonic; the boundary values are g = u at the
// vertices and the source is the exact f = Δu. Probe points: a regular grid
// clipped to the points at least 2% of the domain's diameter inside.
//
// Each point runs N = 16, 32, …, --max-walks walks, incrementally (the walks
// of a point are keyed by point and walk index, so the estimate after N walks
// is the one-shot estimate with N walks), once with and once without control
// variates (the same random streams for both). At every N it reports, over
// the points, the root-mean-square (L2) and maximum (L∞) of the error — the
// Euclidean norm of the error vector for the gradient, the Frobenius norm for
// the Hessian — and the RMS of the reported standard error (the square root
// of the summed variances of the mean of the components).
//
// Usage: GridFreeConvergenceStudy [--max-walks N] [--points N] [--csv path]
//                                 [--seed S] [--threads T]
// Writes the CSV rows walks,control_variates,quantity,l2_error,linf_error,
// mean_stderr; prints a table, the fitted log-log slopes of the errors
// against N and the error ratios without/with control variates at N = 1024.
#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/sources/SourceTerms.h>
#include "TestMeshes.h"
#include "TestSolutions.h"
#include <gridfree/estimators/WalkOnSpheres.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

using namespace gridfree;
using Clock = std::chrono::steady_clock;

namespace
{
constexpr int Quantities = 3; // value, gradient, Hessian
const char* const QuantityNames[Quantities] = { "value", "gradient", "hessian" };

struct Options
{
  int MaxWalks = 16384;
  int Points = 400;
  std::string Csv;
  std::uint64_t Seed = 1;
  int Threads = 2;
};

[[noreturn]] void Usage(const char* message)
{
  std::fprintf(stderr,
    "%s\nusage: GridFreeConvergenceStudy [--max-walks N] [--points N] [--csv path] "
    "[--seed S] [--threads T]\n",
    message);
  std::exit(2);
}

Options ParseOptions(int argc, char** argv)
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        Usage(("missing value after " + arg).c_str());
      }
      return argv[++i];
    };
    if (arg == "--max-walks")
    {
      o.MaxWalks = std::atoi(next().c_str());
    }
    else if (arg == "--points")
    {
      o.Points = std::atoi(next().c_str());
    }
    else if (arg == "--csv")
    {
      o.Csv = next();
    }
    else if (arg == "--seed")
    {
      o.Seed = std::strtoull(next().c_str(), nullptr, 10);
    }
    else if (arg == "--threads")
    {
      o.Threads = std::atoi(next().c_str());
    }
    else if (arg == "--help" || arg == "-h")
    {
      Usage("Convergence of the value, gradient and Hessian estimators (paper Fig. 15).");
    }
    else
    {
      Usage(("unknown argument " + arg).c_str());
    }
  }
  if (o.MaxWalks < 16)
  {
    Usage("--max-walks must be at least 16");
  }
  if (o.Points < 1)
  {
    Usage("--points must be positive");
  }
  return o;
}

// The flower r(θ) = 1 + 0.3 cos 5θ, counter-clockwise. Its curvature changes
// sign between the petals, so the domain is not convex.
testing::SimplexMesh<2> MakeFlower(int segments)
{
  testing::SimplexMesh<2> mesh;
  for (int i = 0; i < segments; ++i)
  {
    const double t = 2.0 * M_PI * i / segments;
    const double r = 1.0 + 0.3 * std::cos(5.0 * t);
    mesh.Vertices.push_back(Vec2(r * std::cos(t), r * std::sin(t)));
    mesh.Simplices.push_back({ i, (i + 1) % segments });
  }
  return mesh;
}

// Crossing-number test against the closed polygon.
bool Inside(const testing::SimplexMesh<2>& mesh, const Vec2& p)
{
  bool inside = false;
  for (const auto& s : mesh.Simplices)
  {
    const Vec2& a = mesh.Vertices[s[0]];
    const Vec2& b = mesh.Vertices[s[1]];
    if ((a[1] > p[1]) != (b[1] > p[1]))
    {
      const double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (p[0] < x)
      {
        inside = !inside;
      }
    }
  }
  return inside;
}

// Nodes of a k × k grid over the bounding box that lie inside, at least
// `margin` from the boundary; k is chosen so the count is closest to target.
std::vector<Vec2> GridPoints(const testing::SimplexMesh<2>& mesh, const Boundary<2>& boundary,
  double margin, int target)
{
  const Vec2 lo = boundary.BoundsMin(), hi = boundary.BoundsMax();
  auto pointsFor = [&](int k) {
    std::vector<Vec2> points;
    for (int j = 0; j < k; ++j)
    {
      for (int i = 0; i < k; ++i)
      {
        const Vec2 p(lo[0] + (hi[0] - lo[0]) * (i + 0.5) / k,
          lo[1] + (hi[1] - lo[1]) * (j + 0.5) / k);
        if (Inside(mesh, p) && boundary.Distance(p) >= margin)
        {
          points.push_back(p);
        }
      }
    }
    return points;
  };
  std::vector<Vec2> best;
  for (int k = 2; k <= 4096; ++k)
  {
    std::vector<Vec2> points = pointsFor(k);
    const bool past = static_cast<int>(points.size()) >= target;
    if (best.empty() ||
      std::abs(static_cast<long>(points.size()) - target) <
        std::abs(static_cast<long>(best.size()) - target))
    {
      best = std::move(points);
    }
    if (past)
    {
      break;
    }
  }
  return best;
}

// f = Δu, the trace of the exact Hessian; ∇f by the default central
// differences.
class LaplacianSource : public VolumeSource<2>
{
public:
  explicit LaplacianSource(const testing::Solution<2>& s)
    : S(s)
  {
  }
  void Evaluate(const Vec2& y, double* f) override { f[0] = this->S.Hessian(y).trace(); }
  bool SupportBounds(Vec2&, Vec2&) const override { return false; }

private:
  const testing::Solution<2>& S;
};

// Least-squares slope of log(error) against log(walks).
double LogLogSlope(const std::vector<int>& walks, const std::vector<double>& error)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(walks.size());
  for (std::size_t k = 0; k < walks.size(); ++k)
  {
    const double x = std::log(static_cast<double>(walks[k])), y = std::log(error[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}
} // namespace

int main(int argc, char** argv)
{
  const Options options = ParseOptions(argc, argv);

  const testing::Solution<2> solution = testing::SmoothSolution<2>();
  const testing::SimplexMesh<2> mesh = MakeFlower(4096);
  std::vector<double> values;
  for (const Vec2& v : mesh.Vertices)
  {
    values.push_back(solution.U(v));
  }
  Boundary<2> boundary;
  boundary.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points, 1, values);

  const double diameter = (boundary.BoundsMax() - boundary.BoundsMin()).maxCoeff();
  const double margin = 0.02 * diameter;
  const std::vector<Vec2> points = GridPoints(mesh, boundary, margin, options.Points);

  std::vector<int> checkpoints;
  for (int n = 16; n <= options.MaxWalks; n *= 2)
  {
    checkpoints.push_back(n);
    if (n > (1 << 29))
    {
      break;
    }
  }
  const int nk = static_cast<int>(checkpoints.size());
  const std::size_t np = points.size();

  WalkSettings settings;
  settings.Problem = Equation::Poisson;
  DerivativeRequest request;
  request.Gradient = true;
  request.Hessian = true;

  std::printf("Poisson problem on the flower r = 1 + 0.3 cos 5t (%zu segments, diameter %.3f)\n",
    boundary.NumberOfPrimitives(), diameter);
  std::printf("u = e^{a.y} sin(b.y) + x^2 y + 1, f = Laplacian of u, epsilon = %g\n",
    settings.Epsilon);
  std::printf("%zu grid points at least %.4f inside; walks 16 .. %d; seed %llu; %d threads\n\n",
    np, margin, checkpoints.back(), static_cast<unsigned long long>(options.Seed),
    options.Threads);
  if (np == 0)
  {
    std::fprintf(stderr, "no probe points inside the domain\n");
    return 1;
  }

  // error[cv][checkpoint][quantity][point], variance likewise (summed over
  // the components of the quantity).
  auto at = [&](int cv, int k, int q, std::size_t i) {
    return ((static_cast<std::size_t>(cv) * nk + k) * Quantities + q) * np + i;
  };
  std::vector<double> error(2 * nk * Quantities * np), variance(2 * nk * Quantities * np);
  std::vector<int> unavailable(2, 0);
  std::atomic<int> interiorFailures{ 0 };

  const auto start = Clock::now();
  double lastReport = 0.0;
  ParallelForWithProgress(
    np, options.Threads,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      LaplacianSource source(solution);
      for (int cv = 0; cv < 2; ++cv)
      {
        DerivativeRequest r = request;
        r.ControlVariates = cv == 1;
        DerivativeWalkOnSpheres<2> estimator(boundary, settings, r, &source);
        const SampleLayout& l = estimator.Layout();
        RunningStatistics stats(l.Size);
        WalkCounters counters;
        for (std::size_t i = begin; i < end; ++i)
        {
          const double xyz[3] = { points[i][0], points[i][1], 0.0 };
          const double exactU = solution.U(points[i]);
          const Vec2 exactG = solution.Gradient(points[i]);
          const Mat<2> exactH = solution.Hessian(points[i]);
          stats.Reset();
          int done = 0;
          for (int k = 0; k < nk; ++k)
          {
            const DerivativeStatus status = estimator.EstimatePoint(
              xyz, options.Seed, static_cast<std::uint64_t>(done), checkpoints[k] - done, stats,
              counters);
            if (status != DerivativeStatus::Interior)
            {
              interiorFailures.fetch_add(1);
            }
            done = checkpoints[k];
            double e2[Quantities] = { 0, 0, 0 }, v[Quantities] = { 0, 0, 0 };
            const double du = stats.GetMean(l.Value) - exactU;
            e2[0] = du * du;
            v[0] = stats.VarianceOfMean(l.Value);
            for (int a = 0; a < 2; ++a)
            {
              const double dg = stats.GetMean(l.Gradient + a) - exactG[a];
              e2[1] += dg * dg;
              v[1] += stats.VarianceOfMean(l.Gradient + a);
              for (int b = 0; b < 2; ++b)
              {
                const double dh = stats.GetMean(l.Hessian + a * 2 + b) - exactH(a, b);
                e2[2] += dh * dh;
                v[2] += stats.VarianceOfMean(l.Hessian + a * 2 + b);
              }
            }
            for (int q = 0; q < Quantities; ++q)
            {
              error[at(cv, k, q, i)] = std::sqrt(e2[q]);
              variance[at(cv, k, q, i)] = v[q];
            }
          }
        }
      }
    },
    [&](double fraction) {
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      if (seconds - lastReport >= 10.0)
      {
        lastReport = seconds;
        std::fprintf(stderr, "  %5.1f%% of the points after %.0f s\n", 100.0 * fraction, seconds);
      }
      return true;
    },
    0.5, 1);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (interiorFailures > 0)
  {
    std::fprintf(stderr, "warning: %d estimates had no first ball centred at the point\n",
      interiorFailures.load());
  }

  // l2[cv][q][k], linf[cv][q][k], stderr[cv][q][k]
  std::vector<double> l2(2 * Quantities * nk), linf(2 * Quantities * nk),
    meanStderr(2 * Quantities * nk);
  auto cell = [&](int cv, int q, int k) { return (cv * Quantities + q) * nk + k; };
  for (int cv = 0; cv < 2; ++cv)
  {
    for (int q = 0; q < Quantities; ++q)
    {
      for (int k = 0; k < nk; ++k)
      {
        double sum2 = 0.0, maximum = 0.0, sumVar = 0.0;
        for (std::size_t i = 0; i < np; ++i)
        {
          const double e = error[at(cv, k, q, i)];
          sum2 += e * e;
          maximum = std::max(maximum, std::isfinite(e) ? e : HUGE_VAL);
          sumVar += variance[at(cv, k, q, i)];
        }
        l2[cell(cv, q, k)] = std::sqrt(sum2 / np);
        linf[cell(cv, q, k)] = maximum;
        meanStderr[cell(cv, q, k)] = std::sqrt(sumVar / np);
      }
    }
  }

  if (!options.Csv.empty())
  {
    std::ofstream csv(options.Csv);
    if (!csv)
    {
      std::fprintf(stderr, "cannot write %s\n", options.Csv.c_str());
      return 1;
    }
    csv << "walks,control_variates,quantity,l2_error,linf_error,mean_stderr\n";
    csv.precision(9);
    for (int k = 0; k < nk; ++k)
    {
      for (int cv = 0; cv < 2; ++cv)
      {
        for (int q = 0; q < Quantities; ++q)
        {
          csv << checkpoints[k] << ',' << cv << ',' << QuantityNames[q] << ','
              << l2[cell(cv, q, k)] << ',' << linf[cell(cv, q, k)] << ','
              << meanStderr[cell(cv, q, k)] << '\n';
        }
      }
    }
  }

  std::printf("%7s %3s | %-29s | %-29s | %-29s\n", "walks", "CV", "value: L2, Linf, stderr",
    "gradient: L2, Linf, stderr", "Hessian: L2, Linf, stderr");
  for (int k = 0; k < nk; ++k)
  {
    for (int cv = 1; cv >= 0; --cv)
    {
      std::printf("%7d %3s", checkpoints[k], cv ? "on" : "off");
      for (int q = 0; q < Quantities; ++q)
      {
        std::printf(" | %9.3e %9.3e %9.3e", l2[cell(cv, q, k)], linf[cell(cv, q, k)],
          meanStderr[cell(cv, q, k)]);
      }
      std::printf("\n");
    }
  }

  std::printf("\nfitted slopes of log error against log walks (expected -0.5):\n");
  for (int cv = 1; cv >= 0; --cv)
  {
    for (int q = 0; q < Quantities; ++q)
    {
      std::vector<double> a(l2.begin() + cell(cv, q, 0), l2.begin() + cell(cv, q, 0) + nk);
      std::vector<double> b(linf.begin() + cell(cv, q, 0), linf.begin() + cell(cv, q, 0) + nk);
      std::printf("  %-8s CV %-3s  L2 %+.3f  Linf %+.3f\n", QuantityNames[q], cv ? "on" : "off",
        nk > 1 ? LogLogSlope(checkpoints, a) : NAN, nk > 1 ? LogLogSlope(checkpoints, b) : NAN);
    }
  }

  int ratioAt = nk - 1;
  for (int k = 0; k < nk; ++k)
  {
    if (checkpoints[k] == 1024)
    {
      ratioAt = k;
    }
  }
  std::printf("\nL2 error without / with control variates at %d walks:", checkpoints[ratioAt]);
  for (int q = 0; q < Quantities; ++q)
  {
    std::printf("  %s %.2fx", QuantityNames[q],
      l2[cell(0, q, ratioAt)] / l2[cell(1, q, ratioAt)]);
  }
  std::printf("\n%.1f s for %zu points x %d walks x 2 settings\n", seconds, np, checkpoints.back());
  return 0;
}
