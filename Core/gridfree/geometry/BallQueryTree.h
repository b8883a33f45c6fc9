// Static bounding-volume tree answering "which boxes overlap this ball?".
//
// Concentrated sources (points, polyline curves) must be looked up at every
// step of every walk, inside the step's empty ball. A walk's ball is usually
// small compared to the source set, so a query must cost O(log n + hits), not
// O(n). Design choices:
//
// * Items are axis-aligned boxes; a point is a degenerate box. The tree only
//   answers the box-ball overlap question; the exact per-item test (point in
//   open ball, segment clipping) belongs to the caller.
// * Build: median split of the box centers along the longest axis of their
//   bounds, O(n log n). Median splits keep the tree balanced for any input
//   (duplicates, collinear points), which bounds the depth and therefore the
//   fixed traversal stack.
// * Nodes live in one flat array in depth-first order: the left child follows
//   its parent, the parent stores the right child's index. Item boxes are
//   copied into leaf order so a leaf is one contiguous block.
// * Overlap means BoundingBox::SquaredDistance(center) <= radius^2 (a closed
//   ball, so the answer is a superset of what an open-ball caller needs).
//   A node box contains its items' boxes, and the rounded distance is
//   monotone in the box bounds, so pruning a node never loses an item that
//   the same per-item test would accept: results equal brute force exactly.
// * Queries are const and allocation free; one tree can serve many threads.
#ifndef GRIDFREE_GEOMETRY_BALL_QUERY_TREE_H
#define GRIDFREE_GEOMETRY_BALL_QUERY_TREE_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace gridfree
{
template <int DIM>
class BallQueryTree
{
public:
  /// Maximum number of items per leaf.
  static constexpr std::size_t kMaxLeafSize = 4;

  BallQueryTree() = default;
  BallQueryTree(const std::vector<Vec<DIM>>& boxMin, const std::vector<Vec<DIM>>& boxMax)
  {
    this->Build(boxMin, boxMax);
  }

  /// Builds the tree over boxes [boxMin[i], boxMax[i]]; O(n log n). Replaces
  /// any previous content. Throws std::invalid_argument if the sizes differ,
  /// a coordinate is not finite or boxMin[i] > boxMax[i] on some axis, and
  /// std::length_error beyond 2^31 items.
  void Build(const std::vector<Vec<DIM>>& boxMin, const std::vector<Vec<DIM>>& boxMax);

  bool Empty() const { return this->ItemIds.empty(); }
  std::size_t Size() const { return this->ItemIds.size(); }

  /// Box of all items (empty box if there are none).
  BoundingBox<DIM> Bounds() const
  {
    return this->Nodes.empty() ? BoundingBox<DIM>() : this->Nodes[0].Box;
  }

  /// Calls visit(itemIndex) once for every item (index as passed to Build)
  /// whose box intersects the closed ball of the given center and radius.
  /// A negative or NaN radius visits nothing; an infinite one visits all.
  template <class Visit>
  void ForEachOverlappingBall(const Vec<DIM>& center, double radius, Visit&& visit) const;

private:
  struct Node
  {
    BoundingBox<DIM> Box;
    // Leaf: Count > 0 items starting at Offset in leaf order.
    // Internal: Count == 0, left child at index + 1, right child at Offset.
    std::uint32_t Offset = 0;
    std::uint32_t Count = 0;
  };

  /// Median splits at least halve the item count per level, so with fewer
  /// than 2^31 items the depth, and the stack of pending right children, is
  /// below 32. The margin costs nothing.
  static constexpr int kStackSize = 64;
  static constexpr std::size_t kMaxItems = std::size_t(1) << 31;

  void BuildNode(std::vector<std::uint32_t>& order, const std::vector<Vec<DIM>>& centers,
    const std::vector<BoundingBox<DIM>>& boxes, std::uint32_t begin, std::uint32_t end);

  std::vector<Node> Nodes;
  std::vector<BoundingBox<DIM>> ItemBoxes; // leaf order
  std::vector<std::uint32_t> ItemIds;      // leaf order -> index given to Build
};

//------------------------------------------------------------------------------
template <int DIM>
void BallQueryTree<DIM>::Build(
  const std::vector<Vec<DIM>>& boxMin, const std::vector<Vec<DIM>>& boxMax)
{
  this->Nodes.clear();
  this->ItemBoxes.clear();
  this->ItemIds.clear();

  if (boxMin.size() != boxMax.size())
  {
    throw std::invalid_argument("gridfree::BallQueryTree: boxMin and boxMax differ in size");
  }
  const std::size_t n = boxMin.size();
  if (n >= kMaxItems)
  {
    throw std::length_error("gridfree::BallQueryTree: too many items");
  }

  std::vector<BoundingBox<DIM>> boxes(n);
  std::vector<Vec<DIM>> centers(n);
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const Vec<DIM>& lo = boxMin[i];
    const Vec<DIM>& hi = boxMax[i];
    if (!lo.allFinite() || !hi.allFinite())
    {
      throw std::invalid_argument("gridfree::BallQueryTree: non-finite box coordinate");
    }
    if ((lo.array() > hi.array()).any())
    {
      throw std::invalid_argument("gridfree::BallQueryTree: box minimum exceeds its maximum");
    }
    boxes[i] = BoundingBox<DIM>(lo, hi);
    centers[i] = boxes[i].Center();
    order[i] = static_cast<std::uint32_t>(i);
  }
  if (n == 0)
  {
    return;
  }

  this->Nodes.reserve(2 * (n / kMaxLeafSize + 1));
  this->BuildNode(order, centers, boxes, 0, static_cast<std::uint32_t>(n));

  this->ItemBoxes.resize(n);
  this->ItemIds = std::move(order);
  for (std::size_t i = 0; i < n; ++i)
  {
    this->ItemBoxes[i] = boxes[this->ItemIds[i]];
  }
}

//------------------------------------------------------------------------------
template <int DIM>
void BallQueryTree<DIM>::BuildNode(std::vector<std::uint32_t>& order,
  const std::vector<Vec<DIM>>& centers, const std::vector<BoundingBox<DIM>>& boxes,
  std::uint32_t begin, std::uint32_t end)
{
  const std::size_t index = this->Nodes.size();
  this->Nodes.emplace_back();

  BoundingBox<DIM> box;
  BoundingBox<DIM> centerBox;
  for (std::uint32_t i = begin; i < end; ++i)
  {
    box.Expand(boxes[order[i]]);
    centerBox.Expand(centers[order[i]]);
  }
  this->Nodes[index].Box = box;

  if (end - begin <= kMaxLeafSize)
  {
    this->Nodes[index].Offset = begin;
    this->Nodes[index].Count = end - begin;
    return;
  }

  // Splitting at the median index (not the median coordinate) guarantees two
  // non-empty halves even when all centers coincide.
  const int axis = centerBox.LongestAxis();
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
    [&](std::uint32_t a, std::uint32_t b) { return centers[a][axis] < centers[b][axis]; });

  this->BuildNode(order, centers, boxes, begin, mid);
  // Nodes may have been reallocated by the recursion: index again.
  this->Nodes[index].Offset = static_cast<std::uint32_t>(this->Nodes.size());
  this->BuildNode(order, centers, boxes, mid, end);
}

//------------------------------------------------------------------------------
template <int DIM>
template <class Visit>
void BallQueryTree<DIM>::ForEachOverlappingBall(
  const Vec<DIM>& center, double radius, Visit&& visit) const
{
  // Written so that a NaN radius is rejected too.
  if (this->Nodes.empty() || !(radius >= 0.0))
  {
    return;
  }
  const double radius2 = radius * radius;

  std::uint32_t stack[kStackSize];
  int top = 0;
  std::uint32_t current = 0;
  for (;;)
  {
    const Node& node = this->Nodes[current];
    if (node.Box.SquaredDistance(center) <= radius2)
    {
      if (node.Count == 0)
      {
        stack[top++] = node.Offset;
        current += 1;
        continue;
      }
      const std::uint32_t last = node.Offset + node.Count;
      for (std::uint32_t i = node.Offset; i < last; ++i)
      {
        if (this->ItemBoxes[i].SquaredDistance(center) <= radius2)
        {
          visit(static_cast<std::size_t>(this->ItemIds[i]));
        }
      }
    }
    if (top == 0)
    {
      return;
    }
    current = stack[--top];
  }
}
} // namespace gridfree

#endif
