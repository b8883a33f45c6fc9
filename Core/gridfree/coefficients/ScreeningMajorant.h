// The screening a walk of the varying equation uses on one ball
// (VaryingCoefficientWalk.h). On B(x, R) the walk writes ΔU − σ′U = f′ as
//
//   ΔU − σ̄ U = f′ − (σ̄ − σ′) U,
//
// which holds for any constant σ̄ ≥ 0, so unbiasedness never depends on the
// choice; the variance and the cost do. A collision at y carries the factor
// σ̄ − σ′(y): positive where σ′ ≤ σ̄, larger than σ̄ where σ′ < 0, negative
// where σ̄ < σ′. So σ̄ should bound σ′ on the ball from above and bound
// 4|σ′| where σ′ is negative (weights at most 5/4), but no larger:
// collisions become more frequent as σ̄R² grows. (With 2|σ′|, weights up to
// 3/2, the CT head's walks were cheaper but the steep tissue interfaces,
// where σ′ has negative lobes, gave error bars with heavier tails.) σ̄ = 0 says that σ′ ≡ 0 on
// the ball (a harmonic step, no collisions).
//
// A floor σ_c ∈ [0, σ̄] below σ′ on the ball lets the walk take the part σ_c
// of the screening as a deterministic weight and collide only for the rest
// (decomposition tracking: Kutz, Habel, Li and Novák, SIGGRAPH 2017, Sec. 5):
// where σ′ hardly varies, as in the brain, the walk is then the
// constant-coefficient screened walk. A floor of 0 is always valid.
//
// A bound per ball rather than one for the whole domain is what keeps the
// walk cheap where the coefficients are flat (Sawhney et al. 2022, Sec. 5,
// suggest bounds over regions): ScreeningBoundGrid samples σ′ on a lattice
// over a box and keeps min/max pyramids, so a ball of any size reads at most
// 2^n cells of the level whose cells are at least its diameter. It keeps the
// same pyramids of the source f′, whose range on a ball lets the walk skip
// most of its source evaluations (VaryingCoefficientWalk.h); like σ′'s, a
// range that misses an extremum costs variance, never bias.
#ifndef GRIDFREE_COEFFICIENTS_SCREENING_MAJORANT_H
#define GRIDFREE_COEFFICIENTS_SCREENING_MAJORANT_H

#include <gridfree/coefficients/VaryingCoefficients.h>
#include <gridfree/execution/PreparationMonitor.h>
#include <gridfree/math/Vector.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

namespace gridfree
{
// What the walk uses on one ball: the majorant σ̄ ≥ 0, a floor
// 0 ≤ σ_c ≤ σ̄ with σ_c ≤ σ′ on the ball, the range [Lowest, Highest]
// that σ′ keeps to on the ball, and the range the source f′ keeps to there
// with the largest |f′| anywhere (SourceScale), all infinite where unknown.
struct BallScreening
{
  double Bound = 0.0;
  double Floor = 0.0;
  double Lowest = 0.0;
  double Highest = 0.0;
  double SourceLowest = -std::numeric_limits<double>::infinity();
  double SourceHighest = std::numeric_limits<double>::infinity();
  double SourceScale = std::numeric_limits<double>::infinity();
};

template <int DIM>
class ScreeningMajorant
{
public:
  virtual ~ScreeningMajorant() = default;
  // σ̄ and σ_c for the ball B(center, radius).
  virtual BallScreening ForBall(const Vec<DIM>& center, double radius) const = 0;
};

// From the lowest and highest σ′ on a region: the σ̄ and σ_c the walk should
// use. The floor stays a sixteenth of σ̄ below it even where σ′ looked
// constant, so the walk keeps colliding now and then: a floor equal to σ̄
// would forbid collisions, and an extremum the sampling missed would then be
// a bias instead of a variance.
inline BallScreening ScreeningFromRange(double lowest, double highest)
{
  BallScreening s;
  s.Lowest = lowest;
  s.Highest = highest;
  s.Bound = std::max({ highest, -4.0 * lowest, 0.0 });
  s.Floor = std::min(std::max(lowest, 0.0), s.Bound * (15.0 / 16.0));
  return s;
}

// One σ̄ (and one floor σ_c, 0 unless given) everywhere, for σ′ in
// [−σ̄/2, σ̄]. A floor equal to σ̄ forbids collisions: exact only where σ′ ≡ σ̄.
template <int DIM>
class ConstantScreeningMajorant final : public ScreeningMajorant<DIM>
{
public:
  explicit ConstantScreeningMajorant(double value, double floor = 0.0)
  {
    if (!(value >= 0.0) || !std::isfinite(value))
    {
      throw std::invalid_argument("the screening majorant must be finite and >= 0");
    }
    if (!(floor >= 0.0) || !(floor <= value))
    {
      throw std::invalid_argument("the screening floor must lie in [0, majorant]");
    }
    this->Value.Bound = value;
    this->Value.Floor = floor;
    this->Value.Lowest = -0.5 * value;
    this->Value.Highest = value;
  }
  BallScreening ForBall(const Vec<DIM>&, double) const override { return this->Value; }

private:
  BallScreening Value;
};

// σ′ sampled on a lattice of (cells·k + 1)^n points over a box; each finest
// cell keeps the lowest and highest sample on its closed cell, widened by
// Margin times their spread (sampling misses extrema between lattice
// points; a miss costs variance, never bias). Coarser levels halve the cells
// per axis and keep the extremes of their children.
template <int DIM>
class ScreeningBoundGrid final : public ScreeningMajorant<DIM>
{
public:
  struct Settings
  {
    int Cells = 32;            // finest cells per axis (rounded up to a power of 2)
    int SamplesPerCell = 3;    // lattice intervals per cell and axis
    double Margin = 0.25;
    // Counts the lattice points sampled and can stop the sampling
    // (PreparationStopped); may be null.
    PreparationMonitor* Monitor = nullptr;
  };

  ScreeningBoundGrid(const CoefficientField<DIM>& field, const Vec<DIM>& boxMin,
    const Vec<DIM>& boxMax, const Settings& settings)
    : Min(boxMin)
  {
    if (!(boxMax - boxMin).allFinite() || !((boxMax - boxMin).minCoeff() > 0.0))
    {
      throw std::invalid_argument("screening bounds: the box must be finite and not flat");
    }
    int cells = 1;
    while (cells < std::max(1, settings.Cells))
    {
      cells *= 2;
    }
    const int k = std::max(1, settings.SamplesPerCell);
    this->CellSize = (boxMax - boxMin) / cells;
    const int lattice = cells * k + 1;
    std::size_t latticePoints = 1;
    for (int i = 0; i < DIM; ++i)
    {
      latticePoints *= static_cast<std::size_t>(lattice);
    }
    std::vector<double> sampled(latticePoints), sampledSource(latticePoints);
    // The first lattice point (in index order) where the coefficients are
    // unusable, so the message names the same place on any thread count.
    std::atomic<std::size_t> firstBad{ latticePoints };
    const Vec<DIM> step = this->CellSize / k;
    auto pointOf = [&](std::size_t index) {
      Vec<DIM> x;
      for (int i = 0; i < DIM; ++i)
      {
        x[i] = boxMin[i] + step[i] * static_cast<double>(index % lattice);
        index /= lattice;
      }
      return x;
    };
    PreparationMonitor* monitor = settings.Monitor;
    if (monitor)
    {
      monitor->Expect(latticePoints);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, latticePoints, 256),
      [&](const tbb::blocked_range<std::size_t>& range) {
        if (monitor && monitor->Stopping())
        {
          return;
        }
        for (std::size_t index = range.begin(); index != range.end(); ++index)
        {
          CoefficientSample<DIM> c;
          field.Evaluate(pointOf(index), c);
          const TransformedCoefficients t = Transform(c);
          sampled[index] = t.Screening;
          sampledSource[index] = t.Source;
          if (!CoefficientsUsable(c) || !std::isfinite(sampled[index]) ||
            !std::isfinite(sampledSource[index]))
          {
            std::size_t seen = firstBad.load();
            while (index < seen && !firstBad.compare_exchange_weak(seen, index))
            {
            }
          }
        }
        if (monitor)
        {
          monitor->Finished(range.size());
        }
      });
    ThrowIfStopped(monitor);
    if (firstBad.load() < latticePoints)
    {
      const Vec<DIM> x = pointOf(firstBad.load());
      CoefficientSample<DIM> c;
      field.Evaluate(x, c);
      throw std::invalid_argument(DescribeUnusable(c, x));
    }

    // Finest level from the lattice.
    Level finest;
    finest.Cells = cells;
    finest.Ranges.assign(CellCount(cells), CellRanges{});
    for (std::size_t cell = 0; cell < finest.Ranges.size(); ++cell)
    {
      std::array<int, DIM> c = Unflatten(cell, cells);
      std::array<int, DIM> offset{};
      CellRanges r;
      for (;;)
      {
        std::size_t index = 0, stride = 1;
        for (int i = 0; i < DIM; ++i)
        {
          index += stride * static_cast<std::size_t>(c[i] * k + offset[i]);
          stride *= static_cast<std::size_t>(lattice);
        }
        r.Take(sampled[index], sampledSource[index]);
        int axis = 0;
        while (axis < DIM && ++offset[axis] > k)
        {
          offset[axis++] = 0;
        }
        if (axis == DIM)
        {
          break;
        }
      }
      r.Widen(settings.Margin);
      finest.Ranges[cell] = r;
    }
    this->Levels.push_back(std::move(finest));
    while (this->Levels.back().Cells > 1)
    {
      const Level& fine = this->Levels.back();
      Level coarse;
      coarse.Cells = fine.Cells / 2;
      coarse.Ranges.assign(CellCount(coarse.Cells), CellRanges{});
      for (std::size_t cell = 0; cell < fine.Ranges.size(); ++cell)
      {
        std::array<int, DIM> c = Unflatten(cell, fine.Cells);
        for (int i = 0; i < DIM; ++i)
        {
          c[i] /= 2;
        }
        coarse.Ranges[Flatten(c, coarse.Cells)].Merge(fine.Ranges[cell]);
      }
      this->Levels.push_back(std::move(coarse));
    }
    const CellRanges& all = this->Levels.back().Ranges.front();
    this->SourceScale = std::max(std::abs(all.SourceLow), std::abs(all.SourceHigh));
  }

  // From the extremes of σ′ (with the margin) over the cells the ball's box
  // touches, on the finest level whose cells are at least its diameter.
  BallScreening ForBall(const Vec<DIM>& center, double radius) const override
  {
    std::size_t level = 0;
    const double diameter = 2.0 * radius;
    while (level + 1 < this->Levels.size() &&
      (this->CellSize.minCoeff() * static_cast<double>(1 << level)) < diameter)
    {
      ++level;
    }
    return this->OnLevel(level, center, radius);
  }

  int LevelCount() const { return static_cast<int>(this->Levels.size()); }

private:
  // The extremes of σ′ and of f′ on a cell, kept side by side so a ball
  // reads both from one place.
  struct CellRanges
  {
    double Low = std::numeric_limits<double>::infinity();
    double High = -std::numeric_limits<double>::infinity();
    double SourceLow = std::numeric_limits<double>::infinity();
    double SourceHigh = -std::numeric_limits<double>::infinity();

    void Take(double screening, double source)
    {
      Low = std::min(Low, screening);
      High = std::max(High, screening);
      SourceLow = std::min(SourceLow, source);
      SourceHigh = std::max(SourceHigh, source);
    }
    void Merge(const CellRanges& o)
    {
      Low = std::min(Low, o.Low);
      High = std::max(High, o.High);
      SourceLow = std::min(SourceLow, o.SourceLow);
      SourceHigh = std::max(SourceHigh, o.SourceHigh);
    }
    void Widen(double margin)
    {
      const double widen = margin * (High - Low);
      Low -= widen;
      High += widen;
      const double widenSource = margin * (SourceHigh - SourceLow);
      SourceLow -= widenSource;
      SourceHigh += widenSource;
    }
  };

  struct Level
  {
    int Cells = 1;
    std::vector<CellRanges> Ranges;
  };

  BallScreening OnLevel(std::size_t level, const Vec<DIM>& center, double radius) const
  {
    const Level& at = this->Levels[level];
    const Vec<DIM> size = this->CellSize * static_cast<double>(1 << level);
    std::array<int, DIM> first, last;
    for (int i = 0; i < DIM; ++i)
    {
      first[i] = this->Clamp((center[i] - radius - this->Min[i]) / size[i], at.Cells);
      last[i] = this->Clamp((center[i] + radius - this->Min[i]) / size[i], at.Cells);
    }
    CellRanges r;
    std::array<int, DIM> c = first;
    for (;;)
    {
      r.Merge(at.Ranges[Flatten(c, at.Cells)]);
      int axis = 0;
      while (axis < DIM && ++c[axis] > last[axis])
      {
        c[axis] = first[axis];
        ++axis;
      }
      if (axis == DIM)
      {
        break;
      }
    }
    BallScreening screening = ScreeningFromRange(r.Low, r.High);
    screening.SourceLowest = r.SourceLow;
    screening.SourceHighest = r.SourceHigh;
    screening.SourceScale = this->SourceScale;
    return screening;
  }

  static std::size_t CellCount(int cells)
  {
    std::size_t n = 1;
    for (int i = 0; i < DIM; ++i)
    {
      n *= static_cast<std::size_t>(cells);
    }
    return n;
  }
  static std::array<int, DIM> Unflatten(std::size_t index, int cells)
  {
    std::array<int, DIM> c;
    for (int i = 0; i < DIM; ++i)
    {
      c[i] = static_cast<int>(index % static_cast<std::size_t>(cells));
      index /= static_cast<std::size_t>(cells);
    }
    return c;
  }
  static std::size_t Flatten(const std::array<int, DIM>& c, int cells)
  {
    std::size_t index = 0, stride = 1;
    for (int i = 0; i < DIM; ++i)
    {
      index += stride * static_cast<std::size_t>(c[i]);
      stride *= static_cast<std::size_t>(cells);
    }
    return index;
  }
  // A cell index from a coordinate in cell units, inside [0, cells − 1]
  // (balls that stick out of the box read its outermost cells).
  static int Clamp(double t, int cells)
  {
    if (!(t > 0.0))
    {
      return 0;
    }
    return static_cast<int>(std::min(t, static_cast<double>(cells - 1)));
  }

  Vec<DIM> Min;
  Vec<DIM> CellSize;
  std::vector<Level> Levels;
  // The largest |f′| sampled anywhere in the box.
  double SourceScale = 0.0;
};
// The coefficients of a problem with their majorant: what a Problem of the
// varying equation holds (both shared, read-only, by every thread).
template <int DIM>
struct CoefficientModel
{
  std::shared_ptr<const CoefficientField<DIM>> Field;
  std::shared_ptr<const ScreeningMajorant<DIM>> Majorant;
};
} // namespace gridfree

#endif
