// The hierarchy's self-check: every primitive in exactly one leaf, every
// child box containing what lies below it (Validate, for the tests).
// Part of the hierarchy of Bvh.h, which includes it after the class: include
// <gridfree/geometry/Bvh.h>, not this file.
#ifndef GRIDFREE_GEOMETRY_BVH_BVH_VALIDATE_H
#define GRIDFREE_GEOMETRY_BVH_BVH_VALIDATE_H

#include <gridfree/geometry/Bvh.h>

namespace gridfree
{
//------------------------------------------------------------------------------
template <int DIM>
bool Bvh<DIM>::Validate() const
{
  if (this->Primitives.empty())
  {
    return this->Nodes.empty() && this->OriginalIds.empty() && this->Groups.empty() &&
      this->Count == 0;
  }
  if (this->Nodes.empty() || this->OriginalIds.size() != this->Primitives.size() ||
    this->Primitives.size() != 4 * this->Groups.size())
  {
    return false;
  }
  // The leaf filter's float copies are the primitives rounded to nearest.
  for (std::size_t i = 0; i < this->Primitives.size(); ++i)
  {
    for (int v = 0; v < DIM; ++v)
    {
      for (int k = 0; k < DIM; ++k)
      {
        if (this->Groups[i / 4].V[v][k][i % 4] !=
          static_cast<float>(this->Primitives[i].V[v][k] - this->Center[k]))
        {
          return false;
        }
      }
    }
  }
  // Every group belongs to exactly one leaf, and every primitive given to
  // Build is in exactly one leaf slot.
  std::vector<char> seenGroups(this->Groups.size(), 0);
  std::vector<char> seenIds(this->Count, 0);
  BoundingBox<DIM> content;
  if (!this->ValidateSubtree(0u, 1, seenGroups, seenIds, content))
  {
    return false;
  }
  auto once = [](char c) { return c == 1; };
  return std::all_of(seenGroups.begin(), seenGroups.end(), once) &&
    std::all_of(seenIds.begin(), seenIds.end(), once);
}

template <int DIM>
bool Bvh<DIM>::ValidateSubtree(std::uint32_t ref, int depth, std::vector<char>& seenGroups,
  std::vector<char>& seenIds, BoundingBox<DIM>& content) const
{
  content = BoundingBox<DIM>();
  if (ref & kLeafFlag)
  {
    const std::size_t group = (ref & ~kLeafFlag) >> 3;
    const std::size_t count = (ref & 7u) + 1;
    const std::size_t groups = (count + 3) / 4;
    if (group + groups > this->Groups.size())
    {
      return false;
    }
    for (std::size_t g = group; g < group + groups; ++g)
    {
      seenGroups[g]++;
    }
    const std::size_t begin = 4 * group;
    for (std::size_t i = begin; i < begin + 4 * groups; ++i)
    {
      if (i >= begin + count)
      {
        // Unused slots repeat the leaf's first primitive.
        if (this->OriginalIds[i] != this->OriginalIds[begin] ||
          std::memcmp(&this->Primitives[i], &this->Primitives[begin], sizeof(PrimitiveData)) != 0)
        {
          return false;
        }
        continue;
      }
      if (this->OriginalIds[i] >= this->Count)
      {
        return false;
      }
      seenIds[this->OriginalIds[i]]++;
      for (const auto& v : this->Primitives[i].V)
      {
        content.Expand(v);
      }
    }
    return true;
  }
  if (ref >= this->Nodes.size() || depth > kMaxDepth)
  {
    return false;
  }
  const Node& node = this->Nodes[ref];
  float lo[DIM][kWidth], hi[DIM][kWidth];
  DecodeBoxes(node, lo, hi);
  for (int c = 0; c < kWidth; ++c)
  {
    if (node.Child[c] == kEmptyChild)
    {
      continue;
    }
    BoundingBox<DIM> box;
    if (!this->ValidateSubtree(node.Child[c], depth + 1, seenGroups, seenIds, box))
    {
      return false;
    }
    for (int k = 0; k < DIM; ++k)
    {
      // Same outward shift as the encoder and the query for the subtraction.
      const double l = box.Min[k] - this->Center[k];
      const double h = box.Max[k] - this->Center[k];
      if (!(lo[k][c] <= l - std::abs(l) * 0x1p-50 && hi[k][c] >= h + std::abs(h) * 0x1p-50))
      {
        return false;
      }
    }
    content.Expand(box);
  }
  return true;
}
} // namespace gridfree

#endif
