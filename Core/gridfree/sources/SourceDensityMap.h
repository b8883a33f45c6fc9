// A piecewise-constant density proportional to |f| for sampling a volume
// source where it is large: the source-density sampling strategy
// (SourceTerms.h, SourceSampling::SourceDensity).
//
// Why: a source much narrower than the domain is found by few walks under
// uniform or Green's-function sampling of each ball, and each walk that
// finds it carries much of the value. The walk values are then heavy-tailed,
// and below a few thousand walks the reported variance is about three times
// too small (User Guide §4, "Error bars you can trust"). Drawing one sample
// per step from a density that follows |f| finds the source whenever the
// ball holds it.
//
// The map: a grid of cells over a box (the source's support, else the
// domain's), each with mass m_j = |cell| · max |f| over its corners and
// centre (all components), and Walker's alias table over the cells (Vose's
// construction), so that a cell is drawn in O(1) with two numbers, then a
// point uniform in it with DIM more. The density is
//   p(y) = m_j / (M |cell|)  for y in cell j,  M = Σ m_j,
// and 0 outside the grid. The estimator combines it with another strategy
// that covers the whole ball (balance heuristic), so the estimate stays
// unbiased whatever the masses: they only set the variance. The map is a
// pure function of f and the box, built once, read by every thread.
//
// Its samples also give f's range (SampledRange) where a source states
// none, for the error bars' bounds of screened walks (Problem::SteadyRange):
// Automatic sampling builds the map for its choice anyway.
#ifndef GRIDFREE_SOURCES_SOURCE_DENSITY_MAP_H
#define GRIDFREE_SOURCES_SOURCE_DENSITY_MAP_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sampling/Random.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace gridfree
{
template <int DIM>
class SourceDensityMap
{
public:
  /// Fills the map over `box` with about `cells` cells (cubic, at least 2
  /// per side), evaluating `source` (a VolumeSource, or anything with
  /// Evaluate(y, f) writing `components` numbers) at every
  /// cell's corners and centre. An empty or degenerate box, or a source
  /// that is zero at every sample, gives an empty map, which samples
  /// nothing (Empty()); the samples' range (SampledRange) is kept either
  /// way.
  template <class Source>
  void Build(Source& source, int components, const BoundingBox<DIM>& box,
    std::size_t cells = 32768)
  {
    *this = SourceDensityMap();
    const Vec<DIM> extent = box.Extent();
    const double longest = extent.maxCoeff();
    if (box.IsEmpty() || !box.Min.allFinite() || !box.Max.allFinite() || !(longest > 0.0) ||
      !std::isfinite(longest) || components < 1 || cells == 0)
    {
      return;
    }
    double volume = 1.0;
    for (int k = 0; k < DIM; ++k)
    {
      volume *= std::max(extent[k], 1e-3 * longest) / longest;
    }
    const double perSide = std::pow(static_cast<double>(cells) / volume, 1.0 / DIM);
    const int cellsLongest = std::max(2, std::min(1024, static_cast<int>(perSide)));
    this->Cell = longest / cellsLongest;
    std::size_t total = 1;
    for (int k = 0; k < DIM; ++k)
    {
      this->Cells[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / this->Cell)));
      this->Origin[k] = box.Min[k];
      total *= static_cast<std::size_t>(this->Cells[k]);
    }
    this->CellVolume = std::pow(this->Cell, DIM);

    // |f| at the grid's vertices (shared by neighbouring cells) and at
    // every cell's centre.
    std::array<int, DIM> vertexCount;
    std::size_t vertices = 1;
    for (int k = 0; k < DIM; ++k)
    {
      vertexCount[k] = this->Cells[k] + 1;
      vertices *= static_cast<std::size_t>(vertexCount[k]);
    }
    // f's components at every vertex, kept for the cells' signed ranges.
    const std::size_t nc = static_cast<std::size_t>(components);
    std::vector<double> f(nc);
    auto magnitude = [&](const Vec<DIM>& y, double* values) {
      source.Evaluate(y, values);
      double largest = 0.0;
      for (std::size_t i = 0; i < nc; ++i)
      {
        largest = std::max(largest, std::abs(values[i])); // NaN is dropped
      }
      return largest;
    };
    std::vector<double> atVertex(vertices);
    std::vector<double> vertexValues(vertices * nc);
    for (std::size_t v = 0; v < vertices; ++v)
    {
      std::array<int, DIM> index;
      std::size_t rest = v;
      for (int k = 0; k < DIM; ++k)
      {
        index[k] = static_cast<int>(rest % static_cast<std::size_t>(vertexCount[k]));
        rest /= static_cast<std::size_t>(vertexCount[k]);
      }
      atVertex[v] = magnitude(this->Corner(index), &vertexValues[v * nc]);
    }
    std::vector<double> low(nc, std::numeric_limits<double>::infinity());
    std::vector<double> high(nc, -std::numeric_limits<double>::infinity());
    std::vector<double> cellLow(nc), cellHigh(nc);
    bool finite = true;
    std::vector<double> mass(total);
    double sum = 0.0;
    for (std::size_t c = 0; c < total; ++c)
    {
      const std::array<int, DIM> index = this->CellIndex(c);
      double largest = magnitude(this->Corner(index) + Vec<DIM>::Constant(0.5 * this->Cell), f.data());
      cellLow = f;
      cellHigh = f;
      for (int corner = 0; corner < (1 << DIM); ++corner)
      {
        std::size_t at = 0;
        std::size_t stride = 1;
        for (int k = 0; k < DIM; ++k)
        {
          at += static_cast<std::size_t>(index[k] + (corner >> k & 1)) * stride;
          stride *= static_cast<std::size_t>(vertexCount[k]);
        }
        largest = std::max(largest, atVertex[at]);
        for (std::size_t i = 0; i < nc; ++i)
        {
          cellLow[i] = std::min(cellLow[i], vertexValues[at * nc + i]);
          cellHigh[i] = std::max(cellHigh[i], vertexValues[at * nc + i]);
        }
      }
      mass[c] = std::isfinite(largest) ? largest * this->CellVolume : 0.0;
      sum += mass[c];
      // A cell's samples widened by their own spread: a function the grid
      // resolves does not leave that band between them.
      for (std::size_t i = 0; i < nc; ++i)
      {
        const double spread = cellHigh[i] - cellLow[i];
        finite = finite && std::isfinite(spread);
        low[i] = std::min(low[i], cellLow[i] - spread);
        high[i] = std::max(high[i], cellHigh[i] + spread);
      }
    }
    if (!(sum > 0.0) || !std::isfinite(sum))
    {
      *this = SourceDensityMap();
      this->KeepRange(finite, std::move(low), std::move(high));
      return;
    }
    this->KeepRange(finite, std::move(low), std::move(high));
    this->TotalMass = sum;
    this->Mass = mass;
    this->BuildAliasTable(mass, sum);
  }

  bool Empty() const { return this->Mass.empty(); }

  /// f's component c over the map's samples, each cell's widened by its
  /// own samples' spread: not a bound (a peak narrower than a cell can pass
  /// between them), so only the error bars' reliability signs read it
  /// (Problem::SteadyRange). False before Build, for a degenerate box and
  /// where a sample was not finite.
  bool SampledRange(int c, double& lowest, double& highest) const
  {
    if (c < 0 || static_cast<std::size_t>(c) >= this->RangeLow.size())
    {
      return false;
    }
    lowest = this->RangeLow[static_cast<std::size_t>(c)];
    highest = this->RangeHigh[static_cast<std::size_t>(c)];
    return true;
  }

  // The share of the cells that hold half of the mass (the heaviest first):
  // small for a source concentrated in a small part of the box, about a
  // half for an even one; 1 for an empty map.
  double HalfMassCellShare() const
  {
    if (this->Mass.empty())
    {
      return 1.0;
    }
    std::vector<double> heaviest(this->Mass);
    std::sort(heaviest.begin(), heaviest.end(), std::greater<double>());
    double held = 0.0;
    std::size_t cells = 0;
    while (cells < heaviest.size() && held < 0.5 * this->TotalMass)
    {
      held += heaviest[cells++];
    }
    return static_cast<double>(cells) / static_cast<double>(heaviest.size());
  }
  // M = Σ m_j: the grid's bound from above on ∫|f| over its box.
  double MassSum() const { return this->TotalMass; }
  std::size_t NumberOfCells() const { return this->Mass.size(); }
  double CellSize() const { return this->Cell; }

  /// A point drawn with density Pdf(); always DIM + 2 random numbers.
  Vec<DIM> Sample(RandomStream& rng) const
  {
    const double u = rng.NextDouble() * static_cast<double>(this->Mass.size());
    std::size_t c = std::min(static_cast<std::size_t>(u), this->Mass.size() - 1);
    if (!(rng.NextDouble() < this->Probability[c]))
    {
      c = this->Alias[c];
    }
    Vec<DIM> y = this->Corner(this->CellIndex(c));
    for (int k = 0; k < DIM; ++k)
    {
      y[k] += rng.NextDouble() * this->Cell;
    }
    return y;
  }

  /// The density at y (0 outside the grid and in cells of no mass).
  double Pdf(const Vec<DIM>& y) const
  {
    if (this->Mass.empty())
    {
      return 0.0;
    }
    std::size_t c = 0;
    std::size_t stride = 1;
    for (int k = 0; k < DIM; ++k)
    {
      const double u = (y[k] - this->Origin[k]) / this->Cell;
      if (!(u >= 0.0 && u < static_cast<double>(this->Cells[k])))
      {
        return 0.0;
      }
      c += static_cast<std::size_t>(u) * stride;
      stride *= static_cast<std::size_t>(this->Cells[k]);
    }
    return this->Mass[c] / (this->TotalMass * this->CellVolume);
  }

private:
  void KeepRange(bool finite, std::vector<double> low, std::vector<double> high)
  {
    if (finite)
    {
      this->RangeLow = std::move(low);
      this->RangeHigh = std::move(high);
    }
  }

  std::array<int, DIM> CellIndex(std::size_t c) const
  {
    std::array<int, DIM> index;
    for (int k = 0; k < DIM; ++k)
    {
      index[k] = static_cast<int>(c % static_cast<std::size_t>(this->Cells[k]));
      c /= static_cast<std::size_t>(this->Cells[k]);
    }
    return index;
  }

  Vec<DIM> Corner(const std::array<int, DIM>& index) const
  {
    Vec<DIM> y;
    for (int k = 0; k < DIM; ++k)
    {
      y[k] = this->Origin[k] + index[k] * this->Cell;
    }
    return y;
  }

  // Vose's alias method: every cell gets probability n m_j / M of keeping
  // its own index, and the rest of its column goes to an alias.
  void BuildAliasTable(const std::vector<double>& mass, double sum)
  {
    const std::size_t n = mass.size();
    this->Probability.assign(n, 1.0);
    this->Alias.resize(n);
    std::vector<double> scaled(n);
    std::vector<std::size_t> small, large;
    for (std::size_t c = 0; c < n; ++c)
    {
      this->Alias[c] = c;
      scaled[c] = mass[c] * static_cast<double>(n) / sum;
      (scaled[c] < 1.0 ? small : large).push_back(c);
    }
    while (!small.empty() && !large.empty())
    {
      const std::size_t s = small.back();
      small.pop_back();
      const std::size_t l = large.back();
      this->Probability[s] = scaled[s];
      this->Alias[s] = l;
      scaled[l] = (scaled[l] + scaled[s]) - 1.0;
      if (scaled[l] < 1.0)
      {
        large.pop_back();
        small.push_back(l);
      }
    }
    // What is left has probability 1 to rounding.
    for (std::size_t c : small)
    {
      this->Probability[c] = 1.0;
    }
    for (std::size_t c : large)
    {
      this->Probability[c] = 1.0;
    }
  }

  std::array<int, DIM> Cells{};
  Vec<DIM> Origin = Vec<DIM>::Zero();
  double Cell = 0.0;
  double CellVolume = 0.0;
  double TotalMass = 0.0;
  std::vector<double> Mass;
  std::vector<double> Probability;
  std::vector<std::size_t> Alias;
  std::vector<double> RangeLow, RangeHigh; // SampledRange, per component
};
} // namespace gridfree

#endif
