// A boundary with mixed conditions for walk on stars (Documentation/
// WalkOnStars.md): a Dirichlet part, where u = g, and a reflecting part,
// where the outward normal derivative is prescribed, ∂u/∂n = h (Neumann).
//
// Each part is a Boundary (Boundary.h) of its own: the Dirichlet part with
// the values g, the reflecting part with the flux h as its values (the same
// number of components). The Dirichlet part gives the walk its distance
// bound and its end values; the reflecting part its rays, its silhouettes
// (SilhouetteTree.h) and the points of the flux term
// (ReflectingBoundarySampler.h).
//
// Orientation is load-bearing on the reflecting part: its normals must point
// out of the domain (2D: the domain on the left of every segment; 3D:
// triangles counter-clockwise seen from outside, VTK's usual outward
// orientation). The flux is taken along that normal, the walk reflects off
// its inner side, and only its reflex vertices or edges are silhouette
// candidates. Where orientations disagree along an edge, that edge is kept
// as a silhouette (stars stay star-shaped there), and a ray that meets a
// primitive from outside counts as a back-face hit (WalkCounters-like
// bookkeeping in the estimator): a sign of an inconsistently oriented or
// leaking surface.
#ifndef GRIDFREE_STARS_MIXED_BOUNDARY_H
#define GRIDFREE_STARS_MIXED_BOUNDARY_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/stars/ReflectingBoundarySampler.h>
#include <gridfree/stars/SilhouetteTree.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gridfree
{
// Boundary condition of a primitive.
enum class BoundaryCondition : std::uint8_t
{
  Dirichlet = 0, // u = g
  Neumann = 1    // ∂u/∂n = h, n the outward normal
};

// One part of a mesh: its own compact vertex list, its primitives, and for
// each primitive its index in the whole mesh.
template <int DIM>
struct MeshPart
{
  using Primitive = std::array<std::int64_t, DIM>;
  std::vector<Vec<DIM>> Vertices;
  std::vector<Primitive> Primitives;
  std::vector<std::int64_t> Original;   // primitive → index in the whole mesh
  std::vector<std::int64_t> VertexOrigin; // vertex → index in the whole mesh
};

// Splits a mesh by the condition of each primitive. Vertices shared by both
// parts appear in both.
template <int DIM>
void SplitByCondition(const std::vector<Vec<DIM>>& vertices,
  const std::vector<std::array<std::int64_t, DIM>>& primitives,
  const std::vector<BoundaryCondition>& conditions, MeshPart<DIM>& dirichlet,
  MeshPart<DIM>& reflecting)
{
  if (conditions.size() != primitives.size())
  {
    throw std::invalid_argument("one boundary condition per primitive expected");
  }
  std::vector<std::int64_t> mapD(vertices.size(), -1), mapR(vertices.size(), -1);
  dirichlet = MeshPart<DIM>();
  reflecting = MeshPart<DIM>();
  for (std::size_t i = 0; i < primitives.size(); ++i)
  {
    const bool isDirichlet = conditions[i] == BoundaryCondition::Dirichlet;
    MeshPart<DIM>& part = isDirichlet ? dirichlet : reflecting;
    std::vector<std::int64_t>& map = isDirichlet ? mapD : mapR;
    std::array<std::int64_t, DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      const std::int64_t v = primitives[i][k];
      if (v < 0 || static_cast<std::size_t>(v) >= vertices.size())
      {
        throw std::invalid_argument("boundary primitive refers to a missing vertex");
      }
      std::int64_t& m = map[static_cast<std::size_t>(v)];
      if (m < 0)
      {
        m = static_cast<std::int64_t>(part.Vertices.size());
        part.Vertices.push_back(vertices[static_cast<std::size_t>(v)]);
        part.VertexOrigin.push_back(v);
      }
      p[k] = m;
    }
    part.Primitives.push_back(p);
    part.Original.push_back(static_cast<std::int64_t>(i));
  }
}

template <int DIM>
class MixedBoundary
{
public:
  // The two parts; either may be null or empty, not both. The reflecting
  // part must be a mesh (it is traced by rays and sampled), with as many
  // value components (the flux) as the Dirichlet part has.
  //
  // `silhouettes` = false leaves the silhouette candidates out, so stars
  // reach the Dirichlet part whatever hides behind the Neumann part's reflex
  // corners: wrong there (biased), right where that part is convex seen from
  // inside. It exists to show what silhouettes are for.
  void Set(std::shared_ptr<const Boundary<DIM>> dirichlet,
    std::shared_ptr<const Boundary<DIM>> reflecting, bool silhouettes = true)
  {
    const bool hasD = dirichlet && !dirichlet->Empty();
    const bool hasR = reflecting && !reflecting->Empty();
    if (!hasD && !hasR)
    {
      throw std::invalid_argument("mixed boundary: both parts are empty");
    }
    if (hasR && !reflecting->IsMesh())
    {
      throw std::invalid_argument("mixed boundary: the Neumann part must be a mesh");
    }
    if (hasD && hasR && dirichlet->Components() != reflecting->Components())
    {
      throw std::invalid_argument("mixed boundary: the Dirichlet values and the Neumann flux "
                                  "must have the same number of components");
    }
    this->DirichletPart = hasD ? std::move(dirichlet) : nullptr;
    this->ReflectingPart = hasR ? std::move(reflecting) : nullptr;
    this->Normals.clear();
    this->Silhouette = SilhouetteTree<DIM>();
    this->Sampler = ReflectingBoundarySampler<DIM>();
    BoundingBox<DIM> box;
    if (hasD)
    {
      box.Expand(this->DirichletPart->BoundsMin());
      box.Expand(this->DirichletPart->BoundsMax());
    }
    if (hasR)
    {
      const auto& v = this->ReflectingPart->MeshVertices();
      const auto& p = this->ReflectingPart->MeshPrimitives();
      if (silhouettes)
      {
        this->Silhouette.Build(v, p);
      }
      this->Sampler.Build(v, p);
      this->Normals.reserve(p.size());
      for (const auto& prim : p)
      {
        this->Normals.push_back(OutwardUnitNormal<DIM>(v, prim));
      }
      box.Expand(this->ReflectingPart->BoundsMin());
      box.Expand(this->ReflectingPart->BoundsMax());
    }
    this->Box = box;
  }

  bool HasDirichlet() const { return static_cast<bool>(this->DirichletPart); }
  bool HasReflecting() const { return static_cast<bool>(this->ReflectingPart); }
  const Boundary<DIM>& Dirichlet() const { return *this->DirichletPart; }
  const Boundary<DIM>& Reflecting() const { return *this->ReflectingPart; }
  const SilhouetteTree<DIM>& Silhouettes() const { return this->Silhouette; }
  const ReflectingBoundarySampler<DIM>& FluxSampler() const { return this->Sampler; }

  int Components() const
  {
    return this->DirichletPart ? this->DirichletPart->Components()
                               : this->ReflectingPart->Components();
  }

  // Unit outward normal of a primitive of the reflecting part.
  const Vec<DIM>& OutwardNormal(std::int64_t primitive) const
  {
    return this->Normals[static_cast<std::size_t>(primitive)];
  }

  const BoundingBox<DIM>& Bounds() const { return this->Box; }
  Vec<DIM> Center() const { return this->Box.Center(); }
  double Diagonal() const { return this->Box.Diagonal(); }

private:
  std::shared_ptr<const Boundary<DIM>> DirichletPart;
  std::shared_ptr<const Boundary<DIM>> ReflectingPart;
  SilhouetteTree<DIM> Silhouette;
  ReflectingBoundarySampler<DIM> Sampler;
  std::vector<Vec<DIM>> Normals;
  BoundingBox<DIM> Box;
};
} // namespace gridfree

#endif
