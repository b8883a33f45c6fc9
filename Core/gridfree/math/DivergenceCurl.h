// ∇·u and ∇×u of a 3-component field from its Jacobian J(i, j) = ∂u_i/∂x_j
// (x_j < DIM; ∂/∂z = 0 in 2D), shared by the derivative walks' samples and
// the sphere cache's.
#ifndef GRIDFREE_MATH_DIVERGENCE_CURL_H
#define GRIDFREE_MATH_DIVERGENCE_CURL_H

namespace gridfree
{
template <int DIM, class Jacobian>
void DivergenceAndCurl(const Jacobian& jacobian, double& divergence, double curl[3])
{
  const auto J = [&](int i, int j) { return j < DIM ? jacobian(i, j) : 0.0; };
  divergence = J(0, 0) + J(1, 1) + J(2, 2);
  curl[0] = J(2, 1) - J(1, 2);
  curl[1] = J(0, 2) - J(2, 0);
  curl[2] = J(1, 0) - J(0, 1);
}
} // namespace gridfree

#endif
