// Inputs found by the libFuzzer target Testing/Fuzz/FuzzBoundaryWalks,
// replayed through the same body (Testing/Fuzz/FuzzBoundaryWalks.h, whose
// header documents the byte layout). Each one crashed the core before its
// fix; a failure now aborts (an invariant) or crashes the test. All are
// contract inputs: finite coordinates, as the VTK filter passes them.
// The full-size fuzzer outputs are in Testing/Fuzz/regressions/.
#include "../../Fuzz/FuzzBoundaryWalks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace gridfree;

namespace
{
int Replay(const std::vector<std::uint8_t>& input)
{
  return fuzz::RunBoundaryWalks(input.data(), input.size());
}
} // namespace

// One triangle with vertices at 1e300 and a probe at the origin: squared
// distances overflow to inf, so Bvh::FindNearest kept no primitive and
// ClosestPoint returned primitive -1, which Boundary::Evaluate used as an
// index (read before the value table) at the end of every walk. The box
// encoder also converted NaN to int (undefined) for bounds beyond floats.
TEST(FuzzRegressions, OverflowingDistancesStillHaveAPrimitive)
{
  EXPECT_EQ(Replay({ 0x00, 0x03, 0x01, 0x01, 0x00, 0xc4, 0xc0, 0xc0, 0xc0, 0xc4, 0xc0, 0xc0,
              0xc0, 0xc4, 0x00, 0x01, 0x02, 0x68, 0x68, 0x68, 0xc0, 0xc0, 0xc0 }),
    0);

  const std::vector<Vec3> vertices = { Vec3(1e300, 0, 0), Vec3(0, 1e300, 0), Vec3(0, 0, 1e300) };
  Boundary<3> boundary;
  boundary.Set(vertices, { { 0, 1, 2 } }, ValueAssociation::Points, 1, { 1.0, 1.0, 1.0 });
  const auto hit = boundary.ClosestPoint(Vec3::Zero());
  EXPECT_EQ(hit.primitive, 0);
  // No closest primitive (a NaN query): NaN, not a read outside the table.
  ClosestPointResult<3> none;
  double value = 0.0;
  boundary.Evaluate(none, &value);
  EXPECT_TRUE(std::isnan(value));
}

// A triangle spanning -1e300..1e300 beside finite ones: its float box is
// infinite, its centre NaN, and the SAH binning converted NaN to int, giving
// bin index INT_MIN: a write far outside the bins (SEGV) in Bvh::Build.
TEST(FuzzRegressions, BuildBinsCentresBeyondTheFloatRange)
{
  EXPECT_EQ(Replay({ 0x00, 0x09, 0x03, 0x01, 0x00, 0xc5, 0xc0, 0xc0, 0xc4, 0x68, 0xc0, 0xc0,
              0xc0, 0x68, 0x68, 0x60, 0x60, 0x70, 0x60, 0x60, 0x68, 0x68, 0x60, 0x78, 0x60, 0x60,
              0x78, 0x68, 0x60, 0x78, 0x60, 0x68, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07,
              0x08, 0x68, 0x68, 0x68, 0x68, 0x68, 0x68, 0x68, 0x68, 0x68, 0x60, 0x60, 0x60 }),
    0);
}

// Five copies of a flat triangle spanning -1e300..1e300 in z = 0: the range's
// half area is inf * 0 = NaN, so Bvh::BuildNode never picked the range to
// split and recursed on it until the stack overflowed.
TEST(FuzzRegressions, BuildSplitsRangesOfNaNArea)
{
  EXPECT_EQ(Replay({ 0x00, 0x03, 0x05, 0x01, 0x00, 0xc5, 0xc0, 0xc0, 0xc4, 0xc0, 0xc0, 0xc0,
              0xc2, 0xc0, 0x00, 0x01, 0x02, 0x00, 0x01, 0x02, 0x00, 0x01, 0x02, 0x00, 0x01, 0x02,
              0x00, 0x01, 0x02, 0x68, 0x68, 0x68, 0xc0, 0xc0, 0xc0 }),
    0);

  const std::vector<Vec3> vertices = { Vec3(-1e300, 0, 0), Vec3(1e300, 0, 0), Vec3(0, 1, 0) };
  Bvh<3> bvh;
  bvh.Build(vertices, std::vector<Bvh<3>::Primitive>(5, { 0, 1, 2 }));
  EXPECT_EQ(bvh.NumberOfPrimitives(), 5u);
  // The triangle kernel itself overflows at 1e300 (a documented limit of
  // double arithmetic): the distance is inf, but the query answers.
  EXPECT_FALSE(std::isnan(bvh.Distance(Vec3(0, 0.5, 2))));
}
