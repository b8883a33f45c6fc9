// Edge-aware denoising of Monte Carlo estimates by a joint bilateral filter
// guided by their variance and by an "albedo" (paper Sec. 5.2.4).
//
// Walk on spheres gives every point an independent, unbiased estimate u_i
// with a known variance v_i, as a path tracer gives every pixel. Renderers
// denoise such images with filters guided by noise-free feature buffers such
// as the albedo; for a PDE the paper takes the boundary value at the closest
// boundary point instead. It is known exactly at every point, and near the
// boundary, where the solution follows the boundary values, it shows the
// solution's sharp features (a jump in the boundary data continues into the
// domain). Its own jumps across the medial axis, where the closest point
// switches between distant parts of the boundary, only stop the averaging
// where the solution is smooth anyway. Here it is the guide a_i.
//
// Each point becomes the weighted mean of itself and its neighbours j:
//
//   w_ij = exp(-d_ij² / (2 σs²))                    spatial Gaussian
//        · exp(-|a_i − a_j|² / (2 σa²))             guide ("albedo")
//        · exp(-D_ij)                               value range
//
//   D_ij = mean over components of
//          max(0, (u_i − u_j)² − (v_i + min(v_i, v_j))) / (k² (v_i + v_j))
//
// D_ij is the variance-normalised distance of Rousselle, Knaus & Zwicker
// 2012 ("Adaptive rendering with non-local means filtering"), taken between
// single points instead of patches, with their α = 1 and their ε only as a
// guard against 0/0. The expected squared difference of two noisy estimates
// of the same value is v_i + v_j, so it is subtracted (the min makes it
// conservative where the noisier point is j) and the rest measured in units
// of the noise. Neighbours whose difference the noise explains get a weight
// near 1; a real edge, many sigmas high, gets none. k (VarianceScale) sets
// how many sigmas count as an edge: larger smooths more.
//
// Design choices:
// * The point itself always takes part, with weight 1 from every term, so the
//   sum of weights is at least 1 and no division can fail.
// * The output variance is Σ w_ij² v_j / (Σ w_ij)², the variance of the
//   weighted mean of independent estimates with the weights held fixed. It
//   ignores that the weights depend on the data and that averaging across a
//   curved solution adds bias: it is the noise left, not the error.
// * The mean is accumulated as u_i + Σ w (u_j − u_i) / Σ w: a region of equal
//   values stays bit for bit equal, and a large offset (temperatures in K)
//   does not cost precision.
// * A point whose value or variance is NaN, infinite or negative is left as
//   it is and is nobody's neighbour, so a bad estimate never spreads. A
//   non-finite guide only switches the guide term off for that pair.
// * Zero variance means an exact value: the range term then admits only
//   neighbours with the very same value.
// * Compared point by point, not patch by patch, the range term is as noisy
//   as the estimates: it favours the neighbours that happen to lie close to
//   the point's own noisy value, so part of that noise stays. A larger k
//   keeps less of it (on a slice of 16-walk estimates, the error left falls
//   1.7-fold from k = 1 to k = 2) at the price of weaker edges that the guide
//   does not show.
// * Every point is computed on its own, summing its neighbours in the order
//   the caller lists them: the result does not depend on the thread count.
#ifndef GRIDFREE_APPLICATIONS_JOINT_BILATERAL_DENOISING_H
#define GRIDFREE_APPLICATIONS_JOINT_BILATERAL_DENOISING_H

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace gridfree
{
struct DenoiseSettings
{
  // Standard deviation of the spatial Gaussian, in world units. 0 keeps only
  // neighbours at the point's own position.
  double SpatialSigma = 1.0;
  // Neighbours farther than this (world units) are ignored; usually
  // kDenoiseRadiusInSigmas × SpatialSigma. Infinite: all that are listed.
  double NeighbourRadius = std::numeric_limits<double>::infinity();
  // k of the range term: an edge must be about k noise sigmas high to stop
  // the averaging. Larger smooths more; 0 averages only equal values.
  double VarianceScale = 1.0;
  // Standard deviation of the guide term, in the guide's units; <= 0 turns
  // the guide term off.
  double GuideSigma = 0.0;
};

// Beyond 2.5 σs the spatial weight is below 0.045: neighbours farther away
// change little and cost much (their number grows like the radius cubed).
constexpr double kDenoiseRadiusInSigmas = 2.5;

// The estimates to denoise, row-major in the caller's arrays: Values and
// Variances hold Count × Components numbers, Guide Count × GuideComponents.
// Without Variances there is no range term (and no output variance); without
// Guide no guide term.
struct DenoiseInput
{
  std::size_t Count = 0;
  int Components = 1;
  const double* Values = nullptr;
  const double* Variances = nullptr;
  int GuideComponents = 0;
  const double* Guide = nullptr;
};

class JointBilateralDenoiser
{
public:
  JointBilateralDenoiser(const DenoiseInput& input, const DenoiseSettings& settings)
    : In(input)
    , Settings(settings)
    , Valid(input.Count, 0)
    , GuideValid(input.Count, 0)
  {
    const std::size_t nc = static_cast<std::size_t>(std::max(input.Components, 0));
    for (std::size_t i = 0; i < input.Count; ++i)
    {
      bool ok = nc > 0;
      for (std::size_t c = 0; c < nc && ok; ++c)
      {
        ok = std::isfinite(input.Values[i * nc + c]);
        if (ok && input.Variances)
        {
          const double v = input.Variances[i * nc + c];
          ok = std::isfinite(v) && v >= 0.0;
        }
      }
      this->Valid[i] = ok ? 1 : 0;
    }
    this->UseGuide = input.Guide && input.GuideComponents > 0 && settings.GuideSigma > 0.0;
    if (this->UseGuide)
    {
      const std::size_t ng = static_cast<std::size_t>(input.GuideComponents);
      for (std::size_t i = 0; i < input.Count; ++i)
      {
        bool ok = true;
        for (std::size_t c = 0; c < ng && ok; ++c)
        {
          ok = std::isfinite(input.Guide[i * ng + c]);
        }
        this->GuideValid[i] = ok ? 1 : 0;
      }
    }
  }

  // Whether point i is denoised and may be a neighbour (finite value,
  // finite non-negative variance).
  bool IsValid(std::size_t i) const { return this->Valid[i] != 0; }

  // Denoises point i into value[0..nc) and, unless null, variance[0..nc)
  // (NaN when the input has no variances). The outputs must not alias the
  // input. forEachNeighbour(i, visit) calls visit(j, squaredDistance) for
  // the neighbours of i, in an order that must not depend on the thread; i
  // itself may be listed or not (it is always counted once), indices out of
  // range are ignored.
  template <class ForEachNeighbour>
  void DenoisePoint(
    std::size_t i, const ForEachNeighbour& forEachNeighbour, double* value, double* variance) const
  {
    const int nc = this->In.Components;
    const double* ui = this->In.Values + i * nc;
    const double* vi = this->In.Variances ? this->In.Variances + i * nc : nullptr;
    if (!this->Valid[i])
    {
      for (int c = 0; c < nc; ++c)
      {
        value[c] = ui[c];
        if (variance)
        {
          variance[c] = vi ? vi[c] : std::numeric_limits<double>::quiet_NaN();
        }
      }
      return;
    }

    // value accumulates Σ w (u_j − u_i), variance Σ w² v_j; the point itself
    // contributes 0 and v_i.
    double sumWeights = 1.0;
    for (int c = 0; c < nc; ++c)
    {
      value[c] = 0.0;
      if (variance && vi)
      {
        variance[c] = vi[c];
      }
    }
    const double radius2 = this->Settings.NeighbourRadius * this->Settings.NeighbourRadius;
    forEachNeighbour(i, [&](std::size_t j, double squaredDistance) {
      if (j == i || j >= this->In.Count || !this->Valid[j] || !(squaredDistance <= radius2))
      {
        return;
      }
      const double w = this->Weight(i, j, squaredDistance);
      if (!(w > 0.0))
      {
        return;
      }
      sumWeights += w;
      const double* uj = this->In.Values + j * nc;
      const double* vj = vi ? this->In.Variances + j * nc : nullptr;
      for (int c = 0; c < nc; ++c)
      {
        value[c] += w * (uj[c] - ui[c]);
        if (variance && vj)
        {
          variance[c] += w * w * vj[c];
        }
      }
    });
    const double inverse = 1.0 / sumWeights;
    for (int c = 0; c < nc; ++c)
    {
      value[c] = ui[c] + value[c] * inverse;
      if (variance)
      {
        variance[c] =
          vi ? variance[c] * inverse * inverse : std::numeric_limits<double>::quiet_NaN();
      }
    }
  }

  // The weight w_ij of neighbour j for point i (both valid), at squared
  // distance d²: one exponential of the three terms' summed exponents.
  double Weight(std::size_t i, std::size_t j, double squaredDistance) const
  {
    double exponent = 0.0;
    if (!AddGaussianExponent(squaredDistance, this->Settings.SpatialSigma, exponent))
    {
      return 0.0;
    }
    if (this->UseGuide && this->GuideValid[i] && this->GuideValid[j])
    {
      const std::size_t ng = static_cast<std::size_t>(this->In.GuideComponents);
      const double* ai = this->In.Guide + i * ng;
      const double* aj = this->In.Guide + j * ng;
      double d2 = 0.0;
      for (std::size_t c = 0; c < ng; ++c)
      {
        d2 += (ai[c] - aj[c]) * (ai[c] - aj[c]);
      }
      if (!AddGaussianExponent(d2, this->Settings.GuideSigma, exponent))
      {
        return 0.0;
      }
    }
    if (this->In.Variances)
    {
      exponent += this->RangeDistance(i, j);
    }
    return std::exp(-exponent);
  }

private:
  // Adds d² / (2 σ²) to `exponent`. Returns false where the weight is 0
  // (d > 0 with σ <= 0 or NaN); d = 0 adds nothing for any σ, so 0/0 never
  // happens. An overflow to infinity is fine: the weight becomes 0.
  static bool AddGaussianExponent(double squaredDistance, double sigma, double& exponent)
  {
    if (squaredDistance <= 0.0)
    {
      return true;
    }
    if (!(sigma > 0.0))
    {
      return false;
    }
    exponent += squaredDistance / (2.0 * sigma * sigma);
    return true;
  }

  // D_ij of the class comment. A component whose excess is not positive adds
  // nothing (no 0/0); with zero variances the guard in the denominator makes
  // any other difference huge, so exact values that differ get weight 0.
  double RangeDistance(std::size_t i, std::size_t j) const
  {
    const int nc = this->In.Components;
    const double* ui = this->In.Values + i * nc;
    const double* uj = this->In.Values + j * nc;
    const double* vi = this->In.Variances + i * nc;
    const double* vj = this->In.Variances + j * nc;
    const double k2 = this->Settings.VarianceScale * this->Settings.VarianceScale;
    double sum = 0.0;
    for (int c = 0; c < nc; ++c)
    {
      const double difference = ui[c] - uj[c];
      const double excess = difference * difference - (vi[c] + std::min(vi[c], vj[c]));
      if (excess > 0.0)
      {
        sum += excess / (k2 * (vi[c] + vj[c]) + std::numeric_limits<double>::min());
      }
    }
    return sum / nc;
  }

  DenoiseInput In;
  DenoiseSettings Settings;
  bool UseGuide = false;
  std::vector<char> Valid;
  std::vector<char> GuideValid;
};

// Denoises every point in parallel: outValues (Count × Components) and, unless
// null, outVariances. forEachNeighbour is called from several threads at once.
template <class ForEachNeighbour>
void JointBilateralDenoise(const DenoiseInput& input, const DenoiseSettings& settings,
  const ForEachNeighbour& forEachNeighbour, double* outValues, double* outVariances)
{
  const JointBilateralDenoiser denoiser(input, settings);
  const std::size_t nc = static_cast<std::size_t>(input.Components);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input.Count, 64),
    [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i)
      {
        denoiser.DenoisePoint(
          i, forEachNeighbour, outValues + i * nc, outVariances ? outVariances + i * nc : nullptr);
      }
    });
}
} // namespace gridfree

#endif
