// Merges a mesh's identical vertices and drops the ones no primitive uses.
//
// Raw isosurface output and many exported meshes are triangle soups: each
// triangle has three vertices of its own, so every vertex is stored about six
// times. The boundary keeps its vertices (double) and their value tuples, so
// on a soup they cost as much as the hierarchy itself. Merging vertices whose
// coordinates AND value tuples are bit for bit equal changes nothing a walk
// can see (the same triangles, the same interpolated values) and removes
// most of that memory.
//
// An open-addressing hash table of 32-bit vertex indices finds the
// duplicates in O(n) expected time with about 12 bytes of scratch per vertex.
#ifndef GRIDFREE_GEOMETRY_WELD_VERTICES_H
#define GRIDFREE_GEOMETRY_WELD_VERTICES_H

#include <gridfree/math/Vector.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace gridfree
{
namespace detail
{
inline std::uint64_t MixBits(std::uint64_t h, double v)
{
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  // A final avalanche (splitmix64) so that nearby coordinates spread.
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  return h;
}
} // namespace detail

/// Renumbers `primitives` so that vertices equal in every coordinate bit and
/// (if `values` is not null) in every bit of their `components` value numbers
/// become one, and keeps only the vertices some primitive uses, in order of
/// first use. `values` (components per vertex, vertex-major) is reduced to
/// match. Primitive indices must be valid. Returns the number of vertices
/// removed; does nothing (returns 0) for more than 2^32 - 2 vertices.
template <int DIM, class Primitive>
std::size_t WeldIdenticalVertices(std::vector<Vec<DIM>>& vertices,
  std::vector<Primitive>& primitives, std::vector<double>* values = nullptr, int components = 0)
{
  const std::size_t n = vertices.size();
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  if (n == 0 || n >= kNone)
  {
    return 0;
  }
  const int nc = values ? components : 0;
  auto hashOf = [&](std::size_t i) {
    std::uint64_t h = 0x84222325cbf29ce4ull;
    for (int k = 0; k < DIM; ++k)
    {
      h = detail::MixBits(h, vertices[i][k]);
    }
    for (int c = 0; c < nc; ++c)
    {
      h = detail::MixBits(h, (*values)[i * nc + c]);
    }
    return h;
  };
  auto same = [&](std::size_t a, std::size_t b) {
    if (std::memcmp(vertices[a].data(), vertices[b].data(), DIM * sizeof(double)) != 0)
    {
      return false;
    }
    return nc == 0 ||
      std::memcmp(&(*values)[a * nc], &(*values)[b * nc], nc * sizeof(double)) == 0;
  };

  // Table of kept OLD indices; at most half full.
  std::size_t size = 1;
  while (size < 2 * n)
  {
    size <<= 1;
  }
  std::vector<std::uint32_t> table(size, kNone);
  // remap[old] = new index, kNone until the vertex is first used.
  std::vector<std::uint32_t> remap(n, kNone);
  std::vector<std::uint32_t> kept; // new index -> old index
  kept.reserve(n / 4);
  for (Primitive& p : primitives)
  {
    for (auto& id : p)
    {
      const std::size_t old = static_cast<std::size_t>(id);
      if (remap[old] == kNone)
      {
        std::size_t slot = static_cast<std::size_t>(hashOf(old)) & (size - 1);
        while (table[slot] != kNone && !same(table[slot], old))
        {
          slot = (slot + 1) & (size - 1);
        }
        if (table[slot] == kNone)
        {
          table[slot] = static_cast<std::uint32_t>(old);
          remap[old] = static_cast<std::uint32_t>(kept.size());
          kept.push_back(static_cast<std::uint32_t>(old));
        }
        else
        {
          remap[old] = remap[table[slot]];
        }
      }
      id = static_cast<typename std::decay<decltype(id)>::type>(remap[old]);
    }
  }
  table = std::vector<std::uint32_t>();
  remap = std::vector<std::uint32_t>();

  // Compact in place: kept old indices are increasing in first use, not in
  // value, so copy through fresh arrays.
  std::vector<Vec<DIM>> newVertices(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i)
  {
    newVertices[i] = vertices[kept[i]];
  }
  vertices = std::move(newVertices);
  if (nc > 0)
  {
    std::vector<double> newValues(kept.size() * nc);
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      std::memcpy(&newValues[i * nc], &(*values)[kept[i] * nc], nc * sizeof(double));
    }
    *values = std::move(newValues);
  }
  return n - kept.size();
}
} // namespace gridfree

#endif
