// The boundary a cache's spheres must stay clear of and whose inside they
// fill: the problem's own boundary, or, with Neumann or Robin parts (walk on
// stars), its two parts joined again into one closed mesh. A sphere inside
// the domain answers by Poisson's formula whatever the conditions on the
// boundary beyond it; only its radius and the inside test need the whole
// boundary.
#ifndef GRIDFREE_CACHE_WHOLE_BOUNDARY_H
#define GRIDFREE_CACHE_WHOLE_BOUNDARY_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/problem/Problem.h>
#include <gridfree/stars/MixedBoundary.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

namespace gridfree
{
// The problem's boundary, or both parts of a mixed one in one mesh (values
// zero: only the geometry is used). The parts' shared vertices (split apart
// by SplitByCondition, with the same coordinates) are welded again, so the
// pseudonormals that decide inside from outside see the whole surface
// around a vertex where the conditions change.
template <int DIM>
std::shared_ptr<const Boundary<DIM>> WholeBoundaryOf(const Problem<DIM>& problem)
{
  const MixedBoundary<DIM>* mixed = problem.GetMixedBoundary();
  if (!mixed || !mixed->HasReflecting() || !mixed->HasDirichlet())
  {
    return problem.SharedBoundary();
  }
  if (!mixed->Dirichlet().IsMesh() || !mixed->Reflecting().IsMesh())
  {
    throw std::invalid_argument("the cache needs a mesh boundary");
  }
  using Primitive = typename Boundary<DIM>::Primitive;
  std::vector<Vec<DIM>> vertices;
  std::vector<Primitive> primitives;
  std::map<std::array<double, DIM>, std::int64_t> welded;
  for (const Boundary<DIM>* part : { &mixed->Dirichlet(), &mixed->Reflecting() })
  {
    const std::vector<Vec<DIM>>& v = part->MeshVertices();
    std::vector<std::int64_t> index(v.size());
    for (std::size_t k = 0; k < v.size(); ++k)
    {
      std::array<double, DIM> key;
      for (int d = 0; d < DIM; ++d)
      {
        key[static_cast<std::size_t>(d)] = v[k][d];
      }
      const auto found = welded.emplace(key, static_cast<std::int64_t>(vertices.size()));
      if (found.second)
      {
        vertices.push_back(v[k]);
      }
      index[k] = found.first->second;
    }
    for (Primitive p : part->MeshPrimitives())
    {
      for (int d = 0; d < DIM; ++d)
      {
        p[d] = index[static_cast<std::size_t>(p[d])];
      }
      primitives.push_back(p);
    }
  }
  const int components = mixed->Dirichlet().Components();
  auto whole = std::make_shared<Boundary<DIM>>();
  whole->Set(std::move(vertices), primitives, ValueAssociation::Cells, components,
    std::vector<double>(primitives.size() * static_cast<std::size_t>(components), 0.0));
  return whole;
}
} // namespace gridfree

#endif
