// The divergence and curl sources of the Helmholtz decomposition, against
// the analytic derivatives of a polynomial vector field.
#include <gridfree/sources/DifferentialOperatorSource.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
// X = (x²y + z, y z² − x, x y z), its first `components` entries,
// differentiated by the base class's central differences.
template <int DIM>
class PolynomialField : public gridfree::VolumeSource<DIM>
{
public:
  explicit PolynomialField(int components = 3)
    : Components(components)
  {
  }
  void Evaluate(const gridfree::Vec<DIM>& p, double* f) override
  {
    const double x = p[0], y = p[1], z = DIM == 3 ? p[2] : 0.0;
    const double all[3] = { x * x * y + z, y * z * z - x, x * y * z };
    // Writing past `components` would overrun the caller's buffer.
    for (int c = 0; c < this->Components; ++c)
    {
      f[c] = all[c];
    }
  }
  bool SupportBounds(gridfree::Vec<DIM>&, gridfree::Vec<DIM>&) const override { return false; }

private:
  int Components;
};
} // namespace

TEST(DifferentialOperatorSource, DivergenceAndCurl3D)
{
  using gridfree::SourceOperator;
  gridfree::DifferentialOperatorSource<3> divergence(
    std::make_unique<PolynomialField<3>>(), 3, SourceOperator::Divergence);
  gridfree::DifferentialOperatorSource<3> curl(
    std::make_unique<PolynomialField<3>>(), 3, SourceOperator::Curl);
  EXPECT_EQ((gridfree::DifferentialOperatorSource<3>::ResultComponents(SourceOperator::Curl)), 3);
  const gridfree::Vec3 p(0.3, -0.7, 1.1);
  const double x = p[0], y = p[1], z = p[2];
  double f[3];
  divergence.Evaluate(p, f);
  EXPECT_NEAR(f[0], 2 * x * y + z * z + x * y, 1e-8);
  curl.Evaluate(p, f);
  EXPECT_NEAR(f[0], x * z - 2 * y * z, 1e-8);
  EXPECT_NEAR(f[1], 1.0 - y * z, 1e-8);
  EXPECT_NEAR(f[2], -1.0 - x * x, 1e-8);
}

TEST(DifferentialOperatorSource, ScalarCurl2D)
{
  using gridfree::SourceOperator;
  gridfree::DifferentialOperatorSource<2> divergence(
    std::make_unique<PolynomialField<2>>(), 3, SourceOperator::Divergence);
  gridfree::DifferentialOperatorSource<2> curl(
    std::make_unique<PolynomialField<2>>(2), 2, SourceOperator::Curl);
  EXPECT_EQ((gridfree::DifferentialOperatorSource<2>::ResultComponents(SourceOperator::Curl)), 1);
  const gridfree::Vec2 p(0.4, 0.9);
  double f[1];
  // In the plane z = 0 no component varies in z.
  divergence.Evaluate(p, f);
  EXPECT_NEAR(f[0], 2 * 0.4 * 0.9, 1e-8);
  curl.Evaluate(p, f);
  EXPECT_NEAR(f[0], -1.0 - 0.4 * 0.4, 1e-8);
}
