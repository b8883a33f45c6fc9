// Coefficients α, σ, f of the varying equation (VaryingCoefficients.h)
// from voxels: a CT scan's tissue properties, or any image.
//
// The walk needs α twice differentiable (σ′ contains Δα), and tissue
// properties are piecewise constant. Each array is therefore smoothed, in
// two stages whose widths add:
//   1. an optional Gaussian of standard deviation `SmoothingWidth` (world
//      units), applied along each axis on the voxels (clamped at the image's
//      edges);
//   2. the cubic B-spline of the (smoothed) voxel values, which is C² with
//      exact derivatives: value Σ c_i β³(t − i), gradient and Laplacian from
//      β³′ and β³″. As an approximation (the voxel values are its
//      coefficients, not its samples) it is itself a smoothing kernel of
//      standard deviation h/√3 per axis, h the spacing.
// The total smoothing along an axis has standard deviation
// sqrt(SmoothingWidth² + h²/3), the modelling width the documentation
// reports. An axis with one voxel (a 2D image in 3D) is constant along it.
// Points outside the image read its edge voxels; whether the image covers
// the domain is the caller's check (Covers).
#ifndef GRIDFREE_COEFFICIENTS_IMAGE_COEFFICIENTS_H
#define GRIDFREE_COEFFICIENTS_IMAGE_COEFFICIENTS_H

#include <gridfree/coefficients/VaryingCoefficients.h>
#include <gridfree/execution/PreparationMonitor.h>
#include <gridfree/math/Vector.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace gridfree
{
// An axis-aligned grid of voxels: point (i, j, k) lies at
// Origin + (i, j, k)·Spacing; arrays hold one number per point, x fastest.
struct VoxelGrid
{
  std::array<double, 3> Origin{};
  std::array<double, 3> Spacing{ 1.0, 1.0, 1.0 };
  std::array<int, 3> Dims{ 1, 1, 1 };

  std::size_t Count() const
  {
    return static_cast<std::size_t>(this->Dims[0]) * static_cast<std::size_t>(this->Dims[1]) *
      static_cast<std::size_t>(this->Dims[2]);
  }
};

// Separable Gaussian smoothing of one array on the grid, standard deviation
// `width` in world units, truncated at 4 widths and normalized, the edge
// voxels repeated beyond the image. width ≤ 0 leaves it unchanged. A
// monitor (may be null) counts the voxels of each pass and can stop it
// (PreparationStopped).
inline std::vector<double> SmoothOnGrid(const VoxelGrid& grid, std::vector<double> values,
  double width, PreparationMonitor* monitor = nullptr)
{
  if (!(width > 0.0))
  {
    return values;
  }
  if (monitor)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (grid.Dims[axis] >= 2)
      {
        monitor->Expect(values.size());
      }
    }
  }
  std::vector<double> scratch(values.size());
  for (int axis = 0; axis < 3; ++axis)
  {
    const int n = grid.Dims[axis];
    const double sigma = width / grid.Spacing[axis];
    if (n < 2 || !(sigma > 0.0))
    {
      continue;
    }
    const int reach = static_cast<int>(std::ceil(4.0 * sigma));
    std::vector<double> kernel(2 * reach + 1);
    double total = 0.0;
    for (int d = -reach; d <= reach; ++d)
    {
      kernel[d + reach] = std::exp(-0.5 * d * d / (sigma * sigma));
      total += kernel[d + reach];
    }
    for (double& k : kernel)
    {
      k /= total;
    }
    std::size_t stride = 1;
    for (int a = 0; a < axis; ++a)
    {
      stride *= static_cast<std::size_t>(grid.Dims[a]);
    }
    // Every output voxel is its own sum, the same on any thread count.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, values.size(), 4096),
      [&](const tbb::blocked_range<std::size_t>& range) {
        if (monitor && monitor->Stopping())
        {
          return;
        }
        for (std::size_t index = range.begin(); index != range.end(); ++index)
        {
          const int i = static_cast<int>((index / stride) % static_cast<std::size_t>(n));
          const std::size_t base = index - static_cast<std::size_t>(i) * stride;
          double sum = 0.0;
          for (int d = -reach; d <= reach; ++d)
          {
            const int j = std::min(std::max(i + d, 0), n - 1);
            sum += kernel[d + reach] * values[base + static_cast<std::size_t>(j) * stride];
          }
          scratch[index] = sum;
        }
        if (monitor)
        {
          monitor->Finished(range.size());
        }
      });
    ThrowIfStopped(monitor);
    values.swap(scratch);
  }
  return values;
}

template <int DIM>
class ImageCoefficients final : public CoefficientField<DIM>
{
public:
  // One coefficient: an array on the grid, or a constant when empty.
  struct Coefficient
  {
    std::vector<double> Values;
    double Constant = 0.0;
  };

  // Smooths each array by `smoothingWidth` (see above). Throws for arrays
  // of the wrong size, non-finite values, α ≤ 0 or σ < 0, naming the array
  // (by `names`: α, σ, f) and the voxel; PreparationStopped when `monitor`
  // (may be null) stops the smoothing.
  ImageCoefficients(const VoxelGrid& grid, Coefficient alpha, Coefficient absorption,
    Coefficient source, double smoothingWidth,
    const std::array<std::string, 3>& names = { "alpha", "sigma", "f" },
    PreparationMonitor* monitor = nullptr)
    : Grid(grid)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (grid.Dims[axis] < 1 || !(grid.Spacing[axis] > 0.0) || !std::isfinite(grid.Spacing[axis]))
      {
        throw std::invalid_argument("coefficient image: dimensions must be >= 1 and spacings "
                                    "positive");
      }
    }
    std::array<Coefficient*, 3> all = { &alpha, &absorption, &source };
    for (int c = 0; c < 3; ++c)
    {
      Coefficient& k = *all[c];
      this->Constant[c] = k.Values.empty();
      if (k.Values.empty())
      {
        this->Check(names[c], c, k.Constant, -1);
        this->ConstantValue[c] = k.Constant;
        continue;
      }
      if (k.Values.size() != grid.Count())
      {
        throw std::invalid_argument("coefficient image: the array " + names[c] + " has " +
          std::to_string(k.Values.size()) + " values for " + std::to_string(grid.Count()) +
          " points");
      }
      for (std::size_t i = 0; i < k.Values.size(); ++i)
      {
        this->Check(names[c], c, k.Values[i], static_cast<std::ptrdiff_t>(i));
      }
      const std::vector<double> smoothed = SmoothOnGrid(grid, std::move(k.Values), smoothingWidth, monitor);
      this->Packed.resize(3 * grid.Count());
      for (std::size_t i = 0; i < smoothed.size(); ++i)
      {
        this->Packed[3 * i + static_cast<std::size_t>(c)] = smoothed[i];
      }
    }
    this->SourceIsZero = this->Constant[2] && this->ConstantValue[2] == 0.0;
  }

  bool HasSource() const override { return !this->SourceIsZero; }

  // Whether the box [lo, hi] lies inside the image's bounds (axes the
  // problem has; an axis with one voxel covers everything).
  bool Covers(const Vec<DIM>& lo, const Vec<DIM>& hi) const
  {
    for (int i = 0; i < DIM; ++i)
    {
      if (this->Grid.Dims[i] < 2)
      {
        continue;
      }
      const double first = this->Grid.Origin[i];
      const double last = first + (this->Grid.Dims[i] - 1) * this->Grid.Spacing[i];
      const double slack = 1e-9 * (last - first);
      if (lo[i] < first - slack || hi[i] > last + slack)
      {
        return false;
      }
    }
    return true;
  }

  void Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const override
  {
    // Per axis: the four voxels (clamped to the image) and the B-spline's
    // weights with their first and second derivatives (per world unit); an
    // axis the problem lacks, or with one voxel, has one tap of weight 1.
    std::array<std::array<std::size_t, 4>, 3> voxel{};
    std::array<std::array<double, 4>, 3> w{}, dw{}, ddw{};
    std::array<int, 3> taps{};
    for (int axis = 0; axis < 3; ++axis)
    {
      const int n = this->Grid.Dims[axis];
      if (axis >= DIM || n < 2)
      {
        taps[axis] = 1;
        voxel[axis][0] = 0;
        w[axis][0] = 1.0;
        continue;
      }
      taps[axis] = 4;
      const double h = this->Grid.Spacing[axis];
      const double t = (x[axis] - this->Grid.Origin[axis]) / h;
      const double cell = std::floor(t);
      Weights(t - cell, w[axis], dw[axis], ddw[axis]);
      const int first = static_cast<int>(cell) - 1;
      for (int k = 0; k < 4; ++k)
      {
        voxel[axis][k] = this->Clamped(first + k, axis);
        dw[axis][k] /= h;
        ddw[axis][k] /= h * h;
      }
    }
    out.AlphaGradient.setZero();
    out.AlphaLaplacian = 0.0;
    // The tensor-product sums one axis at a time: along x for each (y, z)
    // row, then along y, then along z. For α: the value and the first and
    // second derivative along each axis (the Laplacian is their trace).
    // Grouped this way a point costs about 250 multiply-adds instead of 64
    // taps times every product of weights.
    double alpha = 0.0, dx = 0.0, dy = 0.0, dz = 0.0, dxx = 0.0, dyy = 0.0, dzz = 0.0;
    double sigma = 0.0, source = 0.0;
    const std::size_t nx = static_cast<std::size_t>(this->Grid.Dims[0]);
    const std::size_t ny = static_cast<std::size_t>(this->Grid.Dims[1]);
    const bool varyingAlpha = !this->Constant[0];
    const bool varyingSigma = !this->Constant[1];
    const bool varyingSource = !this->Constant[2];
    // The three coefficients of a voxel lie side by side (Packed), so a row
    // of four taps reads two or three cache lines for all of them; a
    // constant coefficient's slot holds zeros and its sums are not used.
    const double* packed = this->Packed.empty() ? nullptr : this->Packed.data();
    if (packed)
    {
      for (int c = 0; c < taps[2]; ++c)
      {
        // Along y for this z: value, ∂x, ∂y, ∂xx, ∂yy of α; values of σ, f.
        double a0 = 0.0, ax = 0.0, ay = 0.0, axx = 0.0, ayy = 0.0, s0 = 0.0, f0 = 0.0;
        for (int b = 0; b < taps[1]; ++b)
        {
          const std::size_t row = nx * (voxel[1][b] + ny * voxel[2][c]);
          double r0 = 0.0, r1 = 0.0, r2 = 0.0, rs = 0.0, rf = 0.0;
          for (int a = 0; a < taps[0]; ++a)
          {
            const double* v = packed + 3 * (row + voxel[0][a]);
            r0 += w[0][a] * v[0];
            r1 += dw[0][a] * v[0];
            r2 += ddw[0][a] * v[0];
            rs += w[0][a] * v[1];
            rf += w[0][a] * v[2];
          }
          a0 += w[1][b] * r0;
          ax += w[1][b] * r1;
          ay += dw[1][b] * r0;
          axx += w[1][b] * r2;
          ayy += ddw[1][b] * r0;
          s0 += w[1][b] * rs;
          f0 += w[1][b] * rf;
        }
        alpha += w[2][c] * a0;
        dx += w[2][c] * ax;
        dy += w[2][c] * ay;
        dz += dw[2][c] * a0;
        dxx += w[2][c] * axx;
        dyy += w[2][c] * ayy;
        dzz += ddw[2][c] * a0;
        sigma += w[2][c] * s0;
        source += w[2][c] * f0;
      }
    }
    if (varyingAlpha)
    {
      out.Alpha = alpha;
      const double gradient[3] = { dx, dy, dz };
      for (int i = 0; i < DIM; ++i)
      {
        out.AlphaGradient[i] = gradient[i];
      }
      out.AlphaLaplacian = dxx + (DIM > 1 ? dyy : 0.0) + (DIM > 2 ? dzz : 0.0);
    }
    else
    {
      out.Alpha = this->ConstantValue[0];
    }
    out.Absorption = varyingSigma ? sigma : this->ConstantValue[1];
    out.Source = varyingSource ? source : this->ConstantValue[2];
  }

private:
  // Cubic B-spline weights of the four voxels around t = cell + u, and
  // their derivatives in u.
  static void Weights(
    double u, std::array<double, 4>& w, std::array<double, 4>& dw, std::array<double, 4>& ddw)
  {
    const double v = 1.0 - u;
    w = { v * v * v / 6.0, (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
      (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0, u * u * u / 6.0 };
    dw = { -0.5 * v * v, (3.0 * u * u - 4.0 * u) / 2.0, (-3.0 * u * u + 2.0 * u + 1.0) / 2.0,
      0.5 * u * u };
    ddw = { v, 3.0 * u - 2.0, -3.0 * u + 1.0, u };
  }

  std::size_t Clamped(int i, int axis) const
  {
    return static_cast<std::size_t>(std::min(std::max(i, 0), this->Grid.Dims[axis] - 1));
  }

  // Refuses an unusable value of coefficient c (0 α, 1 σ, 2 f) at voxel
  // `index` (−1: the constant).
  void Check(const std::string& name, int c, double value, std::ptrdiff_t index) const
  {
    const bool ok = std::isfinite(value) && (c != 0 || value > 0.0) && (c != 1 || value >= 0.0);
    if (ok)
    {
      return;
    }
    std::string where = "the constant";
    if (index >= 0)
    {
      const std::size_t i = static_cast<std::size_t>(index);
      const std::size_t nx = static_cast<std::size_t>(this->Grid.Dims[0]);
      const std::size_t ny = static_cast<std::size_t>(this->Grid.Dims[1]);
      const std::array<std::size_t, 3> ijk = { i % nx, (i / nx) % ny, i / (nx * ny) };
      where = "voxel (" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) + ", " +
        std::to_string(ijk[2]) + ") at (";
      for (int a = 0; a < 3; ++a)
      {
        where += (a ? ", " : "") +
          std::to_string(this->Grid.Origin[a] + static_cast<double>(ijk[a]) * this->Grid.Spacing[a]);
      }
      where += ")";
    }
    const char* rule = c == 0 ? "must be positive and finite"
      : c == 1                ? "must be finite and >= 0"
                              : "must be finite";
    throw std::invalid_argument("coefficient " + name + " " + rule + ": " +
      std::to_string(value) + " at " + where);
  }

  VoxelGrid Grid;
  // α, σ, f of voxel i at 3i, 3i + 1, 3i + 2 (empty when all are constant).
  std::vector<double> Packed;
  std::array<bool, 3> Constant{ { true, true, true } };
  std::array<double, 3> ConstantValue{ { 1.0, 0.0, 0.0 } };
  bool SourceIsZero = true;
};
} // namespace gridfree

#endif
