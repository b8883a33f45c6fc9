// Tests of the branch-free ranking of a node's children (BvhChildOrder.h).
//
// The ranks must give exactly the order of a stable sort by key (ties to the
// lower slot), for every mask and for keys with many ties, signed zeros,
// infinities and subnormals: the SSE build and the portable build (this file
// runs in both) must visit children in the same order, which is what makes
// them return the same primitive among equally near ones.
#include <gridfree/geometry/BvhChildOrder.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <random>
#include <vector>

namespace
{
// The mask's slots in the order a stable sort by key puts them.
std::vector<int> StableOrder(int mask, const std::array<float, 4>& keys)
{
  std::vector<int> slots;
  for (int c = 0; c < 4; ++c)
  {
    if (mask >> c & 1)
    {
      slots.push_back(c);
    }
  }
  std::stable_sort(slots.begin(), slots.end(), [&](int a, int b) { return keys[a] < keys[b]; });
  return slots;
}

void ExpectStableRanks(int mask, const std::array<float, 4>& keys)
{
  int rank[4];
  const int first = gridfree::detail::RankFourChildren(mask, keys.data(), rank);
  const std::vector<int> order = StableOrder(mask, keys);
  ASSERT_FALSE(order.empty());
  EXPECT_EQ(first, order[0]) << "mask " << mask;
  for (std::size_t r = 0; r < order.size(); ++r)
  {
    EXPECT_EQ(rank[order[r]], static_cast<int>(r))
      << "mask " << mask << " keys " << keys[0] << ' ' << keys[1] << ' ' << keys[2] << ' '
      << keys[3];
  }
  // Outside the mask the rank is 0: the searches write those children to
  // the scratch slot above the stack's top.
  for (int c = 0; c < 4; ++c)
  {
    if (!(mask >> c & 1))
    {
      EXPECT_EQ(rank[c], 0) << "mask " << mask << " slot " << c;
    }
  }
}

TEST(BvhChildOrder, RanksAreTheStableOrderForEveryMask)
{
  // Few distinct values, so that most draws have ties; lanes outside the
  // mask may hold anything, NaN included.
  const float inf = std::numeric_limits<float>::infinity();
  const float values[] = { 0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), 1e-30f, 1.0f,
    1.0000001f, 2.0f, -3.0f, 3e38f, inf, -inf };
  const float outside[] = { std::numeric_limits<float>::quiet_NaN(), -inf, 0.0f, 5.0f };
  std::mt19937 rng(20261128);
  std::uniform_int_distribution<int> pickValue(0, static_cast<int>(std::size(values)) - 1);
  std::uniform_int_distribution<int> pickOutside(0, static_cast<int>(std::size(outside)) - 1);
  for (int trial = 0; trial < 20000; ++trial)
  {
    const int mask = 1 + trial % 15;
    std::array<float, 4> keys;
    for (int c = 0; c < 4; ++c)
    {
      keys[c] = (mask >> c & 1) ? values[pickValue(rng)] : outside[pickOutside(rng)];
    }
    ExpectStableRanks(mask, keys);
    if (HasFailure())
    {
      return;
    }
  }
}

TEST(BvhChildOrder, AllEqualKeysKeepSlotOrder)
{
  for (int mask = 1; mask < 16; ++mask)
  {
    ExpectStableRanks(mask, { 2.5f, 2.5f, 2.5f, 2.5f });
    ExpectStableRanks(mask, { 0.0f, -0.0f, 0.0f, -0.0f });
  }
}

TEST(BvhChildOrder, DistinctKeysInEveryPermutation)
{
  std::array<float, 4> keys = { 0.25f, 1.0f, 4.0f, 16.0f };
  do
  {
    for (int mask = 1; mask < 16; ++mask)
    {
      ExpectStableRanks(mask, keys);
    }
  } while (std::next_permutation(keys.begin(), keys.end()));
}
} // namespace
