// Volume sources sampled from images (the VTK module fills the grid from a
// vtkImageData; any C++ caller may fill it from its own voxels).
#ifndef GRIDFREE_SOURCES_IMAGE_SOURCE_H
#define GRIDFREE_SOURCES_IMAGE_SOURCE_H

#include <gridfree/math/Vector.h>
#include <gridfree/sources/SourceTerms.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

namespace gridfree
{
// The grid's 3D point of a problem point: in 2D the plane z = planeZ.
template <int DIM>
std::array<double, 3> ToXYZ(const Vec<DIM>& y, double planeZ)
{
  return { y[0], y[1], DIM == 3 ? y[DIM - 1] : planeZ };
}

// f sampled on a regular grid of voxels (an image), as a volume source:
// trilinear interpolation (direct index arithmetic, honouring the grid's
// direction matrix); zero outside the grid. An axis
// with a single sample is constant along that axis. EvaluateGradient is the
// exact gradient of that interpolant: the derivative of the trilinear weights
// in index space, mapped to world coordinates through (direction · spacing)⁻¹.
// It is continuous inside a voxel and one-sided on the voxels' faces (the
// voxel that Evaluate uses), and zero outside the image.
template <int DIM>
class ImageSource : public VolumeSource<DIM>
{
public:
  // The grid and its values, shared (read-only) by every thread's source.
  struct Shared
  {
    // Physical position of the value array's first point.
    std::array<double, 3> Origin{};
    std::array<double, 3> Spacing{};
    std::array<int, 3> Dims{};
    std::array<double, 9> PhysicalToIndex{}; // inverse direction, row-major
    int Components = 1;
    double PlaneZ = 0.0;
    // Components numbers per point, x fastest, then y, then z.
    std::vector<float> Values;
    // The support's box (SupportBounds) and whether it is bounded (false
    // for a grid with a single sample along an axis of the problem).
    bool Bounded = true;
    Vec<DIM> Min, Max;
  };

  explicit ImageSource(std::shared_ptr<const Shared> shared)
    : Data(std::move(shared))
    , IndexGradient(3 * static_cast<std::size_t>(this->Data->Components))
  {
  }

  void Evaluate(const Vec<DIM>& y, double* f) override { this->Interpolate<false>(y, f, nullptr); }

  // Writes Components() values and Components() × DIM derivatives, like
  // Evaluate (the caller's component count is the same by construction).
  void EvaluateGradient(const Vec<DIM>& y, int, double* f, double* gradient) override
  {
    this->Interpolate<true>(y, f, gradient);
  }

  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    boxMin = this->Data->Min;
    boxMax = this->Data->Max;
    return this->Data->Bounded;
  }

  // Trilinear weights are non-negative and sum to 1, and f is 0 outside the
  // grid: the stored values' range with 0. (A scan of the values: asked
  // once per problem, not per walk.)
  bool ValueBounds(int c, double& lowest, double& highest) const override
  {
    if (c < 0 || c >= this->Data->Components)
    {
      return false;
    }
    StoredValueRange(this->Data->Values, this->Data->Components, c, lowest, highest);
    return std::isfinite(lowest) && std::isfinite(highest);
  }

private:
  // f(y) and, when WithGradient, ∇f(y) (Components × DIM numbers). The value
  // is accumulated in the same order either way, so both paths write the
  // same f.
  template <bool WithGradient>
  void Interpolate(const Vec<DIM>& y, double* f, double* gradient)
  {
    const Shared& s = *this->Data;
    const std::array<double, 3> p = ToXYZ<DIM>(y, s.PlaneZ);
    double index[3];
    int base[3];
    double frac[3];
    for (int i = 0; i < 3; ++i)
    {
      const double d0 = p[0] - s.Origin[0];
      const double d1 = p[1] - s.Origin[1];
      const double d2 = p[2] - s.Origin[2];
      index[i] = (s.PhysicalToIndex[3 * i] * d0 + s.PhysicalToIndex[3 * i + 1] * d1 +
                   s.PhysicalToIndex[3 * i + 2] * d2) /
        s.Spacing[i];
      if (s.Dims[i] == 1)
      {
        base[i] = 0;
        frac[i] = 0.0;
        continue;
      }
      // A tiny tolerance keeps points on the image's faces inside.
      const double top = static_cast<double>(s.Dims[i] - 1);
      if (!(index[i] >= -1e-9 && index[i] <= top + 1e-9))
      {
        std::fill(f, f + s.Components, 0.0);
        if (WithGradient)
        {
          std::fill(gradient, gradient + s.Components * DIM, 0.0);
        }
        return;
      }
      index[i] = std::min(std::max(index[i], 0.0), top);
      base[i] = std::min(static_cast<int>(index[i]), s.Dims[i] - 2);
      frac[i] = index[i] - base[i];
    }
    std::fill(f, f + s.Components, 0.0);
    double* dIndex = this->IndexGradient.data(); // ∂f_c/∂index_k at [3c + k]
    if (WithGradient)
    {
      std::fill(dIndex, dIndex + 3 * s.Components, 0.0);
    }
    const std::size_t strideY = static_cast<std::size_t>(s.Dims[0]);
    const std::size_t strideZ = strideY * static_cast<std::size_t>(s.Dims[1]);
    for (int corner = 0; corner < 8; ++corner)
    {
      double w = 1.0;
      double factor[3]; // the corner's weight factor along each index axis
      std::size_t offset = 0;
      bool skip = false;
      for (int i = 0; i < 3; ++i)
      {
        const int bit = (corner >> i) & 1;
        if (bit && s.Dims[i] == 1)
        {
          skip = true;
          break;
        }
        factor[i] = bit ? frac[i] : 1.0 - frac[i];
        w *= factor[i];
        offset += static_cast<std::size_t>(base[i] + bit) *
          (i == 0 ? 1 : (i == 1 ? strideY : strideZ));
      }
      if (skip)
      {
        continue;
      }
      const float* v = &s.Values[offset * s.Components];
      if (w != 0.0)
      {
        for (int c = 0; c < s.Components; ++c)
        {
          f[c] += w * v[c];
        }
      }
      if (WithGradient)
      {
        // ∂w/∂index_k: the factor along k becomes ±1 (0 along a
        // single-sample axis, where f is constant).
        for (int k = 0; k < 3; ++k)
        {
          if (s.Dims[k] == 1)
          {
            continue;
          }
          const double sign = ((corner >> k) & 1) ? 1.0 : -1.0;
          const double dw = sign * factor[(k + 1) % 3] * factor[(k + 2) % 3];
          if (dw == 0.0)
          {
            continue;
          }
          for (int c = 0; c < s.Components; ++c)
          {
            dIndex[3 * c + k] += dw * v[c];
          }
        }
      }
    }
    if (WithGradient)
    {
      // index_k = Σ_j PhysicalToIndex[k][j]·(p_j − origin_j) / spacing_k, so
      // ∂f/∂p_j = Σ_k ∂f/∂index_k · PhysicalToIndex[k][j] / spacing_k. In 2D
      // y = (p_0, p_1) and p_2 is the fixed plane.
      for (int c = 0; c < s.Components; ++c)
      {
        for (int j = 0; j < DIM; ++j)
        {
          double sum = 0.0;
          for (int k = 0; k < 3; ++k)
          {
            sum += dIndex[3 * c + k] * s.PhysicalToIndex[3 * k + j] / s.Spacing[k];
          }
          gradient[c * DIM + j] = sum;
        }
      }
    }
  }

  std::shared_ptr<const Shared> Data;
  std::vector<double> IndexGradient;
};
} // namespace gridfree

#endif
