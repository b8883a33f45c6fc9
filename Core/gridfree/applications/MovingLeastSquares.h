// Moving least squares (MLS) reconstruction of a function from scattered
// Monte Carlo samples (paper Sec. 5.2.1; Nealen 2004, "An as-short-as-possible
// introduction to the least squares, weighted least squares and moving least
// squares methods for scattered data approximation and interpolation").
//
// At each target point x a polynomial p of degree 0, 1 or 2 in y - x is fitted
// to the k neighbouring samples y_i by weighted least squares; the estimate is
// p(x) and its gradient ∇p(x). Walk on spheres gives each sample a gradient
// from the same walks (Sec. 3.1), so besides the value rows p(y_i) = u_i the
// fit may also ask ∇p(y_i) = ∇u_i (Hermite data): a quadratic then needs only
// four samples in 3D instead of ten, and follows the solution's curvature
// between samples.
//
// Design choices:
// * Coordinates are scaled by the support radius h (s = (y - x) / h), so the
//   normal matrix is well conditioned whatever the model's units, and the
//   gradient rows are h·∇u, commensurate with the value rows.
// * Weights: Wendland's C2 kernel (1 - r)^4 (4 r + 1), r = |y - x| / h, with
//   h a fixed multiple of the distance to the farthest neighbour: smooth in
//   x, so the reconstruction has no seams where the neighbour set changes.
// * Samples lying in a plane or on a line (a slice's samples) make some
//   quadratic terms unobservable. The least-squares problem is solved by a
//   complete orthogonal decomposition, whose minimum-norm solution sets
//   those terms to zero instead of failing.
// * The estimate is linear in the sample data, p(x) = Σ r_j b_j, so its Monte
//   Carlo variance is Σ r_j² Var(b_j) (samples independent): the variance
//   reported is that of the noise carried through the fit. The interpolation
//   bias is not in it (every interpolation scheme has some, Sec. 7).
// * One object per thread: its matrices are reused from point to point.
#ifndef GRIDFREE_APPLICATIONS_MOVING_LEAST_SQUARES_H
#define GRIDFREE_APPLICATIONS_MOVING_LEAST_SQUARES_H

#include <gridfree/math/Vector.h>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <vector>

namespace gridfree
{
// The data of the neighbours of one target point, in the caller's arrays.
// Components are stored per sample: values[i * nc + c], gradients
// [(i * nc + c) * DIM + a]. Null variance pointers mean "unknown" (the
// reported variance is then NaN); null gradients fit values only.
template <int DIM>
struct MlsNeighbours
{
  int Count = 0;
  const Vec<DIM>* Positions = nullptr;
  const double* Values = nullptr;
  const double* ValueVariances = nullptr;
  const double* Gradients = nullptr;
  const double* GradientVariances = nullptr;
};

struct MlsSettings
{
  // Degree of the local polynomial: 0 (weighted average), 1 or 2.
  int Degree = 2;
  // Weight of the gradient rows relative to the value rows (0: values only).
  double GradientWeight = 1.0;
  // h = SupportScale × distance to the farthest neighbour (> 1 so that
  // every neighbour has a positive weight).
  double SupportScale = 1.5;
};

template <int DIM>
class MovingLeastSquares
{
public:
  MovingLeastSquares(const MlsSettings& settings, int components)
    : Settings(settings)
    , Components(components)
  {
    // Terms the samples barely constrain are dropped rather than fitted to
    // the noise (relative to the largest pivot).
    this->Decomposition.setThreshold(1e-9);
  }

  static int NumberOfTerms(int degree)
  {
    return degree <= 0 ? 1 : (degree == 1 ? 1 + DIM : 1 + DIM + DIM * (DIM + 1) / 2);
  }

  // Fits at x. Writes `value` (nc numbers), `gradient` (nc × DIM, may be
  // null) and `variance` (nc, may be null). Returns false, writing NaN, when
  // there is no neighbour.
  bool Fit(const Vec<DIM>& x, const MlsNeighbours<DIM>& data, double* value, double* gradient,
    double* variance)
  {
    const int nc = this->Components;
    const int k = data.Count;
    if (k <= 0)
    {
      this->WriteNaN(value, gradient, variance);
      return false;
    }
    double farthest = 0.0;
    for (int i = 0; i < k; ++i)
    {
      farthest = std::max(farthest, (data.Positions[i] - x).norm());
    }
    // All neighbours at x itself: any positive scale will do.
    const double h = farthest > 0.0 ? this->Settings.SupportScale * farthest : 1.0;

    const bool useGradients = data.Gradients && this->Settings.GradientWeight > 0.0 &&
      this->Settings.Degree > 0;
    const int rowsPerSample = useGradients ? 1 + DIM : 1;
    const int rows = k * rowsPerSample;
    const int terms = NumberOfTerms(this->Settings.Degree);
    this->A.setZero(rows, terms);
    this->B.setZero(rows, nc);
    this->RowVariance.setZero(rows, nc);
    this->RowWeight.setZero(rows);

    for (int i = 0; i < k; ++i)
    {
      const Vec<DIM> s = (data.Positions[i] - x) / h;
      const double r = std::min(1.0, s.norm());
      const double w = std::pow(1.0 - r, 4) * (4.0 * r + 1.0);
      const double sw = std::sqrt(w);
      const int row = i * rowsPerSample;
      this->BasisRow(s, row, sw);
      this->RowWeight(row) = sw;
      for (int c = 0; c < nc; ++c)
      {
        this->B(row, c) = sw * data.Values[i * nc + c];
        this->RowVariance(row, c) =
          data.ValueVariances ? data.ValueVariances[i * nc + c] : kUnknown;
      }
      if (useGradients)
      {
        const double gw = sw * this->Settings.GradientWeight;
        for (int a = 0; a < DIM; ++a)
        {
          this->BasisDerivativeRow(s, a, row + 1 + a, gw);
          this->RowWeight(row + 1 + a) = gw * h;
          for (int c = 0; c < nc; ++c)
          {
            const int index = (i * nc + c) * DIM + a;
            this->B(row + 1 + a, c) = gw * h * data.Gradients[index];
            this->RowVariance(row + 1 + a, c) =
              data.GradientVariances ? data.GradientVariances[index] : kUnknown;
          }
        }
      }
    }

    this->Decomposition.compute(this->A);
    this->Coefficients = this->Decomposition.solve(this->B);
    for (int c = 0; c < nc; ++c)
    {
      value[c] = this->Coefficients(0, c);
      if (gradient)
      {
        for (int a = 0; a < DIM; ++a)
        {
          gradient[c * DIM + a] = this->Settings.Degree > 0 ? this->Coefficients(1 + a, c) / h : 0.0;
        }
      }
    }
    if (variance)
    {
      // p(x) = e0ᵀ A⁺ B: the weights of the data rows are the first row of
      // the pseudo-inverse, times each row's own scaling.
      this->Pseudo = this->Decomposition.pseudoInverse();
      for (int c = 0; c < nc; ++c)
      {
        double sum = 0.0;
        for (int j = 0; j < rows; ++j)
        {
          const double coefficient = this->Pseudo(0, j) * this->RowWeight(j);
          if (coefficient != 0.0)
          {
            sum += coefficient * coefficient * this->RowVariance(j, c);
          }
        }
        variance[c] = sum;
      }
    }
    return true;
  }

private:
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

  // φ(s) into row `row` of A, scaled: 1, s_a, s_a s_b (a <= b).
  void BasisRow(const Vec<DIM>& s, int row, double scale)
  {
    int column = 0;
    this->A(row, column++) = scale;
    if (this->Settings.Degree >= 1)
    {
      for (int a = 0; a < DIM; ++a)
      {
        this->A(row, column++) = scale * s[a];
      }
    }
    if (this->Settings.Degree >= 2)
    {
      for (int a = 0; a < DIM; ++a)
      {
        for (int b = a; b < DIM; ++b)
        {
          this->A(row, column++) = scale * s[a] * s[b];
        }
      }
    }
  }

  // ∂φ/∂s_d (s): 0, δ_ad, ∂(s_a s_b)/∂s_d.
  void BasisDerivativeRow(const Vec<DIM>& s, int d, int row, double scale)
  {
    int column = 1;
    for (int a = 0; a < DIM; ++a)
    {
      this->A(row, column++) = a == d ? scale : 0.0;
    }
    if (this->Settings.Degree >= 2)
    {
      for (int a = 0; a < DIM; ++a)
      {
        for (int b = a; b < DIM; ++b)
        {
          const double derivative = (a == d ? s[b] : 0.0) + (b == d ? s[a] : 0.0);
          this->A(row, column++) = scale * derivative;
        }
      }
    }
  }

  void WriteNaN(double* value, double* gradient, double* variance) const
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int c = 0; c < this->Components; ++c)
    {
      value[c] = nan;
      if (variance)
      {
        variance[c] = nan;
      }
      if (gradient)
      {
        for (int a = 0; a < DIM; ++a)
        {
          gradient[c * DIM + a] = nan;
        }
      }
    }
  }

  MlsSettings Settings;
  int Components;
  Eigen::MatrixXd A, B, RowVariance, Coefficients, Pseudo;
  Eigen::VectorXd RowWeight;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> Decomposition;
};
} // namespace gridfree

#endif
