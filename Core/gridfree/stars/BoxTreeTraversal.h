// The step both of walk on stars' binary box trees (SilhouetteTree.h,
// ReflectingBoundarySampler.h) take when they descend towards a point.
#ifndef GRIDFREE_STARS_BOX_TREE_TRAVERSAL_H
#define GRIDFREE_STARS_BOX_TREE_TRAVERSAL_H

#include <gridfree/math/Vector.h>

#include <cstdint>
#include <vector>

namespace gridfree
{
// Pushes the children `left` and `left + 1` of a node on a depth-first
// stack, the one whose box is nearer to x last, so that it is visited first
// (and the search radius shrinks before the other is looked at).
template <int DIM, class Node>
void PushNearerChildLast(const std::vector<Node>& nodes, std::uint32_t left, const Vec<DIM>& x,
  std::uint32_t* stack, int& top)
{
  const std::uint32_t right = left + 1;
  const bool leftNearer = nodes[left].Box.SquaredDistance(x) <= nodes[right].Box.SquaredDistance(x);
  stack[top++] = leftNearer ? right : left;
  stack[top++] = leftNearer ? left : right;
}
} // namespace gridfree

#endif
