// Gauss–Legendre quadrature shared by the deterministic kernel tests.
#ifndef GRIDFREE_TESTING_QUADRATURE_H
#define GRIDFREE_TESTING_QUADRATURE_H

#include <cmath>
#include <vector>

namespace gridfree
{
namespace testing
{
// Gauss-Legendre nodes and weights on [-1, 1] by Newton on P_n.
struct GaussLegendre
{
  explicit GaussLegendre(int n)
  {
    for (int i = 0; i < n; ++i)
    {
      double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
      double derivative = 1.0;
      for (int iteration = 0; iteration < 100; ++iteration)
      {
        double p0 = 1.0;
        double p1 = x;
        for (int k = 2; k <= n; ++k)
        {
          const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        derivative = n * (x * p1 - p0) / (x * x - 1.0);
        const double step = p1 / derivative;
        x -= step;
        if (std::abs(step) < 1e-16)
        {
          break;
        }
      }
      this->Nodes.push_back(x);
      this->Weights.push_back(2.0 / ((1.0 - x * x) * derivative * derivative));
    }
  }

  std::vector<double> Nodes;
  std::vector<double> Weights;
};

} // namespace testing
} // namespace gridfree

#endif
