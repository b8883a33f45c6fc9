// Singularities of a cross field (CrossField.h) by the winding of ψ around
// the cells of a grid: a search that cannot miss a winding.
//
// The winding number of ψ around a closed loop on which ψ ≠ 0 is the sum of
// the indices of the zeros of ψ inside it (degree theory: ψ need not be
// holomorphic). Gradient descent from seeds can stop short of a flat zero
// (|ψ| ~ r² around a zero of winding ±2) or miss one no seed rolls to; the
// winding of the cells of a grid covering the domain accounts for every zero
// inside the grid, because the windings of all cells add up, edge by edge,
// to the winding around the grid's outer loop.
//
// With noisy estimates the phase of ψ along an edge is only known where |ψ|
// stands out of the noise, and between two samples only if the phase turns
// by less than MaxPhaseStep: the samples' wrapped phase difference, and the
// phase's rate along the edge at each sample (Im(∂ψ/ψ) from the estimated
// gradient) times the spacing, must both stay below it; and no zero may be
// within half the spacing of a sample, to first order: |ψ| > (h/2)·‖∇ψ‖
// (‖·‖ the Frobenius norm of the Jacobian, so |ψ|/‖∇ψ‖ is at most the
// first-order distance to the nearest zero). These catch a zero passing
// between two samples, around which the phase turns by a whole 2π that
// their difference alone cannot see, and a zero on the edge itself (a
// symmetric shape puts one on a grid line), which stays unresolved however
// finely the edge is split. So:
//  - the phase change along an edge is the sum of the wrapped changes
//    between consecutive samples on it, computed once per edge and used with
//    opposite signs by its two cells (so the cell windings add up exactly);
//  - an edge whose samples do not resolve it is split (a batch of midpoints
//    per round) up to MaxEdgeSplits times;
//  - an edge still unresolved (a zero on or next to it) joins its two cells
//    into one region, whose winding is taken around the region's outer
//    edges; a region that reaches an unresolved outer edge of the grid is
//    counted as unresolved;
//  - a region with a non-zero winding is split into four cells per cell and
//    searched again, up to MaxLevels times, as long as its parts' windings
//    add up to its own; the singularities are the smallest regions with a
//    non-zero winding, placed at the centroid of their cells, with that
//    winding as Index (in quarter units of the cross-field index).
// The sum of the indices found is then checked against the boundary's
// (Poincaré–Hopf; BoundaryWindingOfPolygon) by the caller.
#ifndef GRIDFREE_APPLICATIONS_CROSS_FIELD_WINDING_H
#define GRIDFREE_APPLICATIONS_CROSS_FIELD_WINDING_H

#include <gridfree/applications/CrossField.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

namespace gridfree
{
struct WindingSearchSettings
{
  // Cells along the longer side of the box (square cells).
  int GridCells = 16;
  // Times a region with a non-zero winding is split into finer cells.
  int MaxLevels = 5;
  // Times an edge is split in two while its samples do not resolve it.
  int MaxEdgeSplits = 4;
  // A sample's phase counts when |ψ| > NoiseFactor · sd(ψ).
  double NoiseFactor = 3.0;
  // Consecutive samples on an edge resolve it when their phases differ by
  // less than this, and the phase's rate at each times their spacing too.
  double MaxPhaseStep = M_PI / 2.0;
};

struct WindingSearchStatistics
{
  std::size_t EvaluatorCalls = 0;
  std::size_t EvaluatedPoints = 0;
  int GridCellsInside = 0;       // level-0 cells wholly inside the domain
  int UnresolvedRegions = 0;     // regions reaching an unresolved outer edge
  int OuterWinding = 0;          // sum of the resolved level-0 regions' windings
  bool Aborted = false;          // the evaluator failed; nothing is returned
};

// The winding of ψ = ν⁴ (ν the outward normal) around the boundary, just
// inside it: along a straight side ψ is constant; at a corner, where the
// boundary turns by α, ψ follows the chord from ν₁⁴ to ν₂⁴ and turns by 4α
// wrapped into (−π, π]. The sum over the corners, over 2π, is what the
// indices of the singularities inside must add up to (Poincaré–Hopf: 4χ for
// a smooth boundary, χ the Euler characteristic). `loops` are the boundary's
// closed loops, each in order with the domain on its left (counter-
// clockwise around the outside, clockwise around holes), without repeating
// the first vertex. A corner with 4α ≡ π (a 45° turn) puts a zero of ψ on
// the boundary: `ambiguous` is then set.
inline int BoundaryWinding(const std::vector<std::vector<Vec2>>& loops, bool* ambiguous = nullptr)
{
  if (ambiguous)
  {
    *ambiguous = false;
  }
  double total = 0.0;
  for (const std::vector<Vec2>& vertices : loops)
  {
    const std::size_t n = vertices.size();
    for (std::size_t i = 0; n >= 3 && i < n; ++i)
    {
      const Vec2 d0 = vertices[i] - vertices[(i + n - 1) % n];
      const Vec2 d1 = vertices[(i + 1) % n] - vertices[i];
      if (!(d0.squaredNorm() > 0.0) || !(d1.squaredNorm() > 0.0))
      {
        continue;
      }
      const double turn = std::atan2(d0.x() * d1.y() - d0.y() * d1.x(), d0.dot(d1));
      const double change = detail::WrapAngle(4.0 * turn);
      if (ambiguous && std::abs(std::abs(change) - M_PI) < 1e-9)
      {
        *ambiguous = true;
      }
      total += change;
    }
  }
  return static_cast<int>(std::lround(total / (2.0 * M_PI)));
}

// The same for a simple polygon, in either orientation.
inline int BoundaryWindingOfPolygon(std::vector<Vec2> vertices, bool* ambiguous = nullptr)
{
  double area = 0.0;
  for (std::size_t i = 0; i < vertices.size(); ++i)
  {
    const Vec2& a = vertices[i];
    const Vec2& b = vertices[(i + 1) % vertices.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  if (area < 0.0)
  {
    std::reverse(vertices.begin(), vertices.end());
  }
  return BoundaryWinding({ vertices }, ambiguous);
}

namespace detail
{
// The search's lattice: points are integer coordinates in units of the
// finest spacing (a level-0 cell is `Unit` units wide), so that samples are
// shared between cells, edges and levels.
class WindingLattice
{
public:
  using Key = std::pair<std::int64_t, std::int64_t>;

  WindingLattice(const Vec2& origin, double cellSize, std::int64_t unit)
    : Origin(origin)
    , Spacing(cellSize / static_cast<double>(unit))
  {
  }

  Vec2 Position(const Key& k) const
  {
    return this->Origin + this->Spacing * Vec2(static_cast<double>(k.first), static_cast<double>(k.second));
  }

  bool Has(const Key& k) const { return this->Samples.count(k) > 0; }
  const CrossFieldSample& At(const Key& k) const { return this->Samples.at(k); }

  // Evaluates the points of `wanted` not yet known, in one call.
  bool Evaluate(const CrossFieldEvaluator& evaluator, std::vector<Key> wanted,
    WindingSearchStatistics& stats)
  {
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    wanted.erase(std::remove_if(wanted.begin(), wanted.end(),
                   [this](const Key& k) { return this->Has(k); }),
      wanted.end());
    if (wanted.empty())
    {
      return true;
    }
    std::vector<Vec2> points;
    points.reserve(wanted.size());
    for (const Key& k : wanted)
    {
      points.push_back(this->Position(k));
    }
    std::vector<CrossFieldSample> out;
    if (!EvaluateBatch(evaluator, points, out, stats.EvaluatorCalls, stats.EvaluatedPoints))
    {
      stats.Aborted = true;
      return false;
    }
    for (std::size_t i = 0; i < wanted.size(); ++i)
    {
      this->Samples.emplace(wanted[i], out[i]);
    }
    return true;
  }

private:
  Vec2 Origin;
  double Spacing;
  std::map<Key, CrossFieldSample> Samples;
};

// An axis-aligned edge of the lattice from A to B (A < B), its samples in
// order, and the phase change of ψ along it.
struct WindingEdge
{
  WindingLattice::Key A, B;
  std::vector<WindingLattice::Key> Points;
  double Change = 0.0;
  bool Resolved = false;
};

// One level of the search: square cells (lower-left corner, width in
// lattice units), their edges, and the regions that unresolved edges join.
struct WindingRegion
{
  std::vector<std::size_t> Cells;
  int Winding = 0;
  bool Resolved = true;
};

class WindingLevel
{
public:
  struct Cell
  {
    WindingLattice::Key Corner;
    std::int64_t Width;
  };

  explicit WindingLevel(std::vector<Cell> cells)
    : Cells(std::move(cells))
  {
  }

  // Computes every edge's phase change, splitting the unresolved ones, and
  // the regions; false when the evaluator failed.
  bool Solve(const CrossFieldEvaluator& evaluator, WindingLattice& lattice,
    const WindingSearchSettings& settings, WindingSearchStatistics& stats)
  {
    // The edges, each once, with the cells on either side.
    std::vector<WindingLattice::Key> corners;
    for (std::size_t c = 0; c < this->Cells.size(); ++c)
    {
      const auto& k = this->Cells[c].Corner;
      const std::int64_t w = this->Cells[c].Width;
      const WindingLattice::Key p00 = k, p10 = { k.first + w, k.second },
                                p01 = { k.first, k.second + w }, p11 = { k.first + w, k.second + w };
      // Counter-clockwise: bottom (+), right (+), top (−), left (−) in the
      // edges' own A→B direction.
      this->AddEdge(p00, p10, c, +1);
      this->AddEdge(p10, p11, c, +1);
      this->AddEdge(p01, p11, c, -1);
      this->AddEdge(p00, p01, c, -1);
      corners.insert(corners.end(), { p00, p10, p01, p11 });
    }
    if (!lattice.Evaluate(evaluator, corners, stats))
    {
      return false;
    }
    for (auto& entry : this->Edges)
    {
      entry.second.Points = { entry.second.A, entry.second.B };
    }
    for (int split = 0;; ++split)
    {
      std::vector<WindingLattice::Key> wanted;
      for (auto& entry : this->Edges)
      {
        WindingEdge& e = entry.second;
        this->Measure(e, lattice, settings);
        if (e.Resolved || split == settings.MaxEdgeSplits)
        {
          continue;
        }
        // Split every piece of an unresolved edge that can still be split.
        std::vector<WindingLattice::Key> refined;
        for (std::size_t i = 0; i + 1 < e.Points.size(); ++i)
        {
          refined.push_back(e.Points[i]);
          const auto& p = e.Points[i];
          const auto& q = e.Points[i + 1];
          if ((q.first - p.first + q.second - p.second) % 2 == 0)
          {
            const WindingLattice::Key mid = { (p.first + q.first) / 2, (p.second + q.second) / 2 };
            refined.push_back(mid);
            wanted.push_back(mid);
          }
        }
        refined.push_back(e.Points.back());
        e.Points = std::move(refined);
      }
      if (wanted.empty())
      {
        break;
      }
      if (!lattice.Evaluate(evaluator, wanted, stats))
      {
        return false;
      }
    }
    this->FindRegions();
    return true;
  }

  const std::vector<Cell>& GetCells() const { return this->Cells; }
  const std::vector<WindingRegion>& Regions() const { return this->RegionList; }

private:
  struct Side
  {
    std::size_t Cell;
    int Sign;
  };

  static std::pair<WindingLattice::Key, WindingLattice::Key> EdgeKey(
    const WindingLattice::Key& a, const WindingLattice::Key& b)
  {
    return { a, b };
  }

  void AddEdge(const WindingLattice::Key& a, const WindingLattice::Key& b, std::size_t cell, int sign)
  {
    auto it = this->Edges.find(EdgeKey(a, b));
    if (it == this->Edges.end())
    {
      WindingEdge e;
      e.A = a;
      e.B = b;
      it = this->Edges.emplace(EdgeKey(a, b), e).first;
    }
    this->Sides[EdgeKey(a, b)].push_back({ cell, sign });
  }

  // The rate of arg ψ along the unit direction u at a sample: Im(∂_u ψ / ψ).
  static double PhaseRate(const CrossFieldSample& a, const Vec2& u)
  {
    const std::complex<double> du(u.dot(a.GradRe), u.dot(a.GradIm));
    return (du / a.Psi).imag();
  }

  // No zero of ψ within half a spacing of the sample, to first order.
  static bool FarFromZero(const CrossFieldSample& a, double spacing)
  {
    const double jacobian = std::sqrt(a.GradRe.squaredNorm() + a.GradIm.squaredNorm());
    return std::abs(a.Psi) > 0.5 * spacing * jacobian;
  }

  static void Measure(WindingEdge& e, const WindingLattice& lattice, const WindingSearchSettings& s)
  {
    e.Change = 0.0;
    e.Resolved = true;
    const Vec2 direction = lattice.Position(e.B) - lattice.Position(e.A);
    const Vec2 u = direction.normalized();
    for (std::size_t i = 0; i < e.Points.size(); ++i)
    {
      const CrossFieldSample& a = lattice.At(e.Points[i]);
      if (!IsUsable(a) || !(std::abs(a.Psi) > NoiseFloor(a, s.NoiseFactor)))
      {
        e.Resolved = false;
      }
      if (i + 1 < e.Points.size())
      {
        const CrossFieldSample& b = lattice.At(e.Points[i + 1]);
        const double spacing =
          (lattice.Position(e.Points[i + 1]) - lattice.Position(e.Points[i])).norm();
        const double step = WrapAngle(std::arg(b.Psi) - std::arg(a.Psi));
        e.Resolved = e.Resolved && std::abs(step) < s.MaxPhaseStep &&
          std::abs(PhaseRate(a, u)) * spacing < s.MaxPhaseStep &&
          std::abs(PhaseRate(b, u)) * spacing < s.MaxPhaseStep && FarFromZero(a, spacing) &&
          FarFromZero(b, spacing);
        e.Change += step;
      }
    }
    e.Resolved = e.Resolved && std::isfinite(e.Change);
  }

  std::size_t Find(std::size_t c)
  {
    while (this->Parent[c] != c)
    {
      this->Parent[c] = this->Parent[this->Parent[c]];
      c = this->Parent[c];
    }
    return c;
  }

  void FindRegions()
  {
    const std::size_t n = this->Cells.size();
    this->Parent.resize(n);
    std::iota(this->Parent.begin(), this->Parent.end(), std::size_t(0));
    for (const auto& entry : this->Sides)
    {
      const auto& sides = entry.second;
      if (sides.size() == 2 && !this->Edges.at(entry.first).Resolved)
      {
        this->Parent[this->Find(sides[0].Cell)] = this->Find(sides[1].Cell);
      }
    }
    std::map<std::size_t, std::size_t> regionOf;
    for (std::size_t c = 0; c < n; ++c)
    {
      const std::size_t root = this->Find(c);
      auto it = regionOf.find(root);
      if (it == regionOf.end())
      {
        it = regionOf.emplace(root, this->RegionList.size()).first;
        this->RegionList.emplace_back();
      }
      this->RegionList[it->second].Cells.push_back(c);
    }
    std::vector<double> change(this->RegionList.size(), 0.0);
    for (const auto& entry : this->Sides)
    {
      const auto& sides = entry.second;
      const WindingEdge& e = this->Edges.at(entry.first);
      const std::size_t first = regionOf.at(this->Find(sides[0].Cell));
      if (sides.size() == 2 && regionOf.at(this->Find(sides[1].Cell)) == first)
      {
        continue; // inside one region
      }
      for (const Side& side : sides)
      {
        const std::size_t r = regionOf.at(this->Find(side.Cell));
        change[r] += side.Sign * e.Change;
        if (!e.Resolved)
        {
          this->RegionList[r].Resolved = false; // an unresolved outer edge
        }
      }
    }
    for (std::size_t r = 0; r < this->RegionList.size(); ++r)
    {
      this->RegionList[r].Winding = static_cast<int>(std::lround(change[r] / (2.0 * M_PI)));
    }
  }

  std::vector<Cell> Cells;
  std::map<std::pair<WindingLattice::Key, WindingLattice::Key>, WindingEdge> Edges;
  std::map<std::pair<WindingLattice::Key, WindingLattice::Key>, std::vector<Side>> Sides;
  std::vector<std::size_t> Parent;
  std::vector<WindingRegion> RegionList;
};
} // namespace detail

// The zeros of ψ inside the box [boxMin, boxMax], found by winding (see
// above). `inside` says whether a point lies in the domain; a cell is
// searched when its corners are inside and at least half its diagonal from
// the boundary (BoundaryDistance), so that the whole cell is. Each
// singularity's Index is the winding of its region; Radius is half the
// region's extent; SeedCount the cells of the region.
inline std::vector<Singularity> FindSingularitiesByWinding(const CrossFieldEvaluator& evaluator,
  const std::function<bool(const Vec2&)>& inside, const Vec2& boxMin, const Vec2& boxMax,
  const WindingSearchSettings& settings = {}, WindingSearchStatistics* statistics = nullptr)
{
  WindingSearchStatistics local;
  WindingSearchStatistics& stats = statistics ? *statistics : local;
  stats = WindingSearchStatistics{};
  std::vector<Singularity> result;
  const Vec2 extent = boxMax - boxMin;
  if (!evaluator || !(extent.x() > 0.0) || !(extent.y() > 0.0) || !detail::IsFinite(extent))
  {
    return result;
  }
  const int levels = std::max(0, settings.MaxLevels);
  const std::int64_t unit = std::int64_t(1) << (levels + std::max(0, settings.MaxEdgeSplits));
  const double cell = std::max(extent.x(), extent.y()) / std::max(1, settings.GridCells);
  const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / cell - 1e-9)));
  const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / cell - 1e-9)));
  const Vec2 origin = boxMin + 0.5 * (extent - cell * Vec2(nx, ny));
  detail::WindingLattice lattice(origin, cell, unit);

  // Level 0: the grid's corners, then the cells wholly inside.
  std::vector<detail::WindingLattice::Key> corners;
  for (int j = 0; j <= ny; ++j)
  {
    for (int i = 0; i <= nx; ++i)
    {
      const detail::WindingLattice::Key k = { i * unit, j * unit };
      if (inside(lattice.Position(k)))
      {
        corners.push_back(k);
      }
    }
  }
  if (!lattice.Evaluate(evaluator, corners, stats))
  {
    return result;
  }
  const double halfDiagonal = cell * std::sqrt(0.5);
  auto cornerInside = [&](const detail::WindingLattice::Key& k) {
    if (!lattice.Has(k))
    {
      return false;
    }
    const CrossFieldSample& s = lattice.At(k);
    return s.Valid && s.BoundaryDistance > halfDiagonal;
  };
  std::vector<detail::WindingLevel::Cell> cells;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const detail::WindingLattice::Key k = { i * unit, j * unit };
      if (cornerInside(k) && cornerInside({ k.first + unit, k.second }) &&
        cornerInside({ k.first, k.second + unit }) && cornerInside({ k.first + unit, k.second + unit }))
      {
        cells.push_back({ k, unit });
      }
    }
  }
  stats.GridCellsInside = static_cast<int>(cells.size());
  if (cells.empty())
  {
    return result;
  }

  // A region to report: its cells' centroid and extent.
  auto report = [&](const std::vector<detail::WindingLevel::Cell>& regionCells, int winding) {
    Vec2 sum = Vec2::Zero();
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    Vec2 hi = -lo;
    double minPsi = std::numeric_limits<double>::infinity();
    for (const auto& c : regionCells)
    {
      const Vec2 a = lattice.Position(c.Corner);
      const Vec2 b = lattice.Position({ c.Corner.first + c.Width, c.Corner.second + c.Width });
      sum += 0.5 * (a + b);
      lo = lo.cwiseMin(a);
      hi = hi.cwiseMax(b);
      for (const auto& k : { c.Corner, detail::WindingLattice::Key{ c.Corner.first + c.Width, c.Corner.second },
             detail::WindingLattice::Key{ c.Corner.first, c.Corner.second + c.Width },
             detail::WindingLattice::Key{ c.Corner.first + c.Width, c.Corner.second + c.Width } })
      {
        minPsi = std::min(minPsi, std::abs(lattice.At(k).Psi));
      }
    }
    Singularity s;
    s.Position = sum / static_cast<double>(regionCells.size());
    s.Index = winding;
    s.PhaseWinding = winding;
    s.PsiMagnitude = minPsi;
    s.SeedCount = static_cast<int>(regionCells.size());
    s.Radius = 0.5 * (hi - lo).maxCoeff();
    s.IndexSampleCount = static_cast<int>(regionCells.size()) * 4;
    result.push_back(s);
  };

  // Search a set of cells at `level`; regions with a non-zero winding are
  // split and searched again while their parts add up to them.
  std::function<bool(std::vector<detail::WindingLevel::Cell>, int, int)> search =
    [&](std::vector<detail::WindingLevel::Cell> levelCells, int level, int expected) -> bool {
    detail::WindingLevel grid(std::move(levelCells));
    if (!grid.Solve(evaluator, lattice, settings, stats))
    {
      return false;
    }
    int total = 0;
    bool allResolved = true;
    for (const detail::WindingRegion& r : grid.Regions())
    {
      total += r.Resolved ? r.Winding : 0;
      allResolved = allResolved && r.Resolved;
    }
    if (level == 0)
    {
      stats.OuterWinding = total;
      for (const detail::WindingRegion& r : grid.Regions())
      {
        stats.UnresolvedRegions += r.Resolved ? 0 : 1;
      }
    }
    else if (!allResolved || total != expected)
    {
      return false; // the parts do not account for the whole: keep it whole
    }
    for (const detail::WindingRegion& r : grid.Regions())
    {
      if (!r.Resolved || r.Winding == 0)
      {
        continue;
      }
      std::vector<detail::WindingLevel::Cell> regionCells;
      for (std::size_t c : r.Cells)
      {
        regionCells.push_back(grid.GetCells()[c]);
      }
      bool split = false;
      if (level < levels)
      {
        std::vector<detail::WindingLevel::Cell> children;
        for (const auto& c : regionCells)
        {
          const std::int64_t h = c.Width / 2;
          for (int q = 0; q < 4; ++q)
          {
            children.push_back({ { c.Corner.first + (q % 2) * h, c.Corner.second + (q / 2) * h }, h });
          }
        }
        const std::size_t before = result.size();
        split = search(std::move(children), level + 1, r.Winding);
        if (stats.Aborted)
        {
          return false;
        }
        if (!split)
        {
          result.resize(before);
        }
      }
      if (!split)
      {
        report(regionCells, r.Winding);
      }
    }
    return true;
  };
  if (!search(std::move(cells), 0, 0) || stats.Aborted)
  {
    result.clear();
  }
  return result;
}
} // namespace gridfree

#endif
