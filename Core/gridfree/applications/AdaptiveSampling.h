// The two decisions of adaptive sampling (paper Sec. 5.2.2, in the spirit of
// Ward & Heckbert's irradiance gradients): where the first samples go, and
// whether a candidate point needs a sample of its own.
//
// * First samples: the candidate nearest to the centre of each occupied cell
//   of a uniform grid, the cell size found by bisection so that about the
//   requested number of cells is occupied. This spreads samples evenly over
//   any candidate set (an image, an oblique slice, a point cloud) without
//   knowing its dimension, and is deterministic.
// * Refinement: the k nearest samples y_i each predict the value at x by
//   their first-order Taylor expansion u_i + ∇u_i · (x − y_i). Where the
//   solution is close to linear over the neighbourhood the predictions agree;
//   where it curves, or a wall or source lies between, they spread. The
//   paper refines where "the sample variance divided by the mean" of the
//   predictions exceeds σ. Here the spread is measured as a standard
//   deviation against a scale the caller chooses (by default the range of
//   the solution), because a harmonic u + c is as smooth as u while its
//   variance/mean changes with c. Monte Carlo noise also spreads the
//   predictions: its expected share, the mean of Var(u_i) + Σ (x−y_i)_a²
//   Var(∂_a u_i), is subtracted, so a threshold below the noise does not
//   refine everywhere.
#ifndef GRIDFREE_APPLICATIONS_ADAPTIVE_SAMPLING_H
#define GRIDFREE_APPLICATIONS_ADAPTIVE_SAMPLING_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace gridfree
{
using Point3 = std::array<double, 3>;

namespace detail
{
// Cell of p in a grid of cell size h anchored at `origin`.
inline std::array<std::int64_t, 3> GridCell(const Point3& p, const Point3& origin, double h)
{
  return { static_cast<std::int64_t>(std::floor((p[0] - origin[0]) / h)),
    static_cast<std::int64_t>(std::floor((p[1] - origin[1]) / h)),
    static_cast<std::int64_t>(std::floor((p[2] - origin[2]) / h)) };
}

struct CellHash
{
  std::size_t operator()(const std::array<std::int64_t, 3>& c) const
  {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int64_t v : c)
    {
      h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    }
    return static_cast<std::size_t>(h);
  }
};

// For each occupied cell, the index of the point nearest its centre (ties:
// the lower index). Non-finite points are skipped.
inline std::vector<std::size_t> PointsNearestCellCentres(
  const std::vector<Point3>& points, const Point3& origin, double h)
{
  struct Best
  {
    std::size_t Index;
    double Distance;
  };
  std::unordered_map<std::array<std::int64_t, 3>, Best, CellHash> cells;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Point3& p = points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      continue;
    }
    const auto cell = GridCell(p, origin, h);
    double d = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double centre = origin[a] + (static_cast<double>(cell[a]) + 0.5) * h;
      d += (p[a] - centre) * (p[a] - centre);
    }
    auto found = cells.find(cell);
    if (found == cells.end())
    {
      cells.emplace(cell, Best{ i, d });
    }
    else if (d < found->second.Distance)
    {
      found->second = Best{ i, d };
    }
  }
  std::vector<std::size_t> chosen;
  chosen.reserve(cells.size());
  for (const auto& entry : cells)
  {
    chosen.push_back(entry.second.Index);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}
} // namespace detail

// About `count` well-spread indices into `points` (all of them when there are
// no more than `count`), in increasing order.
inline std::vector<std::size_t> SpreadSubset(const std::vector<Point3>& points, std::size_t count)
{
  Point3 lo = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity() };
  Point3 hi = { -lo[0], -lo[1], -lo[2] };
  std::size_t finite = 0;
  for (const Point3& p : points)
  {
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
    {
      ++finite;
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
    }
  }
  const double diagonal = finite == 0 ? 0.0
                                      : std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                          (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (count == 0 || finite == 0)
  {
    return {};
  }
  if (finite <= count || diagonal == 0.0)
  {
    std::vector<std::size_t> all;
    for (std::size_t i = 0; i < points.size() && all.size() < (diagonal == 0.0 ? 1 : finite); ++i)
    {
      const Point3& p = points[i];
      if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
      {
        all.push_back(i);
      }
    }
    return all;
  }
  // Occupied cells fall as the cell size grows: bisect log h between a size
  // that separates far more points than asked and the whole box.
  double small = diagonal * 1e-7, large = 2.0 * diagonal;
  std::vector<std::size_t> best = detail::PointsNearestCellCentres(points, lo, large);
  for (int iteration = 0; iteration < 40; ++iteration)
  {
    const double h = std::sqrt(small * large);
    std::vector<std::size_t> chosen = detail::PointsNearestCellCentres(points, lo, h);
    const auto difference = [count](std::size_t n) {
      return n > count ? n - count : count - n;
    };
    if (difference(chosen.size()) < difference(best.size()))
    {
      best = chosen;
    }
    if (chosen.size() > count)
    {
      small = h;
    }
    else
    {
      large = h;
    }
    if (chosen.size() == count || large / small < 1.0 + 1e-6)
    {
      break;
    }
  }
  return best;
}

// One neighbour's contribution to the refinement test at x: its value and
// gradient (first component), their variances, and its position.
struct TaylorNeighbour
{
  Point3 Position;
  double Value;
  Point3 Gradient;
  double ValueVariance;
  Point3 GradientVariance;
};

// Spread of the neighbours' Taylor predictions at x beyond what their Monte
// Carlo noise explains: (sample variance of the predictions) − (mean of their
// variances), a squared quantity in the units of u. Infinite with fewer than
// two neighbours (nothing to compare: sample there).
inline double TaylorDisagreement(const Point3& x, const TaylorNeighbour* neighbours, int count)
{
  if (count < 2)
  {
    return std::numeric_limits<double>::infinity();
  }
  double mean = 0.0, meanSquare = 0.0, noise = 0.0;
  for (int i = 0; i < count; ++i)
  {
    const TaylorNeighbour& n = neighbours[i];
    double prediction = n.Value;
    double variance = n.ValueVariance;
    for (int a = 0; a < 3; ++a)
    {
      const double offset = x[a] - n.Position[a];
      prediction += n.Gradient[a] * offset;
      variance += offset * offset * n.GradientVariance[a];
    }
    mean += prediction;
    meanSquare += prediction * prediction;
    noise += variance;
  }
  mean /= count;
  const double spread = (meanSquare - count * mean * mean) / (count - 1);
  return spread - noise / count;
}
} // namespace gridfree

#endif
