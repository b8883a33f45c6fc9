// A boundary with mixed conditions for walk on stars (Documentation/
// WalkOnStars.md): a Dirichlet part, where u = g, and a reflecting part,
// where ∂u/∂n + μu = h with n the outward normal: Neumann where μ = 0,
// Robin where μ > 0 (a coefficient per primitive).
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
// primitive from outside is counted (WalkOnStarsEstimator::BackFaceHits):
// the sign of an inconsistently oriented or leaking surface.
#ifndef GRIDFREE_STARS_MIXED_BOUNDARY_H
#define GRIDFREE_STARS_MIXED_BOUNDARY_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/geometry/RayParity.h>
#include <gridfree/stars/ReflectingBoundarySampler.h>
#include <gridfree/stars/RobinRadius.h>
#include <gridfree/stars/SilhouetteTree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gridfree
{
// Boundary condition of a primitive.
enum class BoundaryCondition : std::uint8_t
{
  Dirichlet = 0,      // u = g
  Neumann = 1,        // ∂u/∂n = h, n the outward normal
  Robin = 2,          // ∂u/∂n + μu = h, μ > 0
  InsulatingSheet = 3 // ∂u/∂n = 0 on both sides: the domain lies on both
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
  // `robin` holds μ >= 0 per primitive of the reflecting part (empty: all
  // 0, a Neumann part); Robin primitives bound the stars' radii so that the
  // walk's weights stay in [0, 1] (RobinRadius).
  //
  // `silhouettes` = false leaves the silhouette candidates out, so stars
  // reach the Dirichlet part whatever hides behind the Neumann part's reflex
  // corners: wrong there (biased), right where that part is convex seen from
  // inside. It exists to show what silhouettes are for.
  //
  // `twoSided` marks, per primitive of the reflecting part (empty: none),
  // insulating sheets: surfaces inside the domain with the domain on both
  // sides and no flux through them (their flux values are not read, their
  // μ must be 0). Walks reflect off either side; they close nothing (Inside
  // ignores them) and their orientation does not matter.
  //
  // `exterior` makes the domain the outside of the closed boundary (3D
  // Laplace: u → 0 at infinity, and WalkOnStars.h returns far walks
  // exactly; the screened equation without sources: far walks end).
  // The mesh keeps its orientation (normals out of the object) and the flux
  // h is still ∂u/∂n along them: internally the domain's outward normal is
  // their opposite, h changes sign and silhouettes are taken for that side.
  // A Robin condition ∂u/∂n + μu = h is taken along the normal out of the
  // domain solved, on either side, so that μ > 0 keeps the problem
  // well posed and h/μ stays what the surface exchanges with (h does not
  // change sign on Robin primitives; FluxSign).
  void Set(std::shared_ptr<const Boundary<DIM>> dirichlet,
    std::shared_ptr<const Boundary<DIM>> reflecting, std::vector<double> robin = {},
    bool silhouettes = true, std::vector<std::uint8_t> twoSided = {}, bool exterior = false)
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
    const std::size_t reflectingPrimitives = hasR ? reflecting->NumberOfPrimitives() : 0;
    if (!robin.empty() && robin.size() != reflectingPrimitives)
    {
      throw std::invalid_argument("mixed boundary: expected one Robin coefficient per primitive "
                                  "of the Neumann part");
    }
    for (double mu : robin)
    {
      if (!(mu >= 0.0) || !std::isfinite(mu))
      {
        throw std::invalid_argument("mixed boundary: Robin coefficients must be finite and >= 0");
      }
    }
    if (!twoSided.empty() && twoSided.size() != reflectingPrimitives)
    {
      throw std::invalid_argument("mixed boundary: expected one two-sided flag per primitive of "
                                  "the Neumann part");
    }
    for (std::size_t i = 0; i < twoSided.size() && !robin.empty(); ++i)
    {
      if (twoSided[i] && robin[i] > 0.0)
      {
        throw std::invalid_argument(
          "mixed boundary: an insulating sheet has no Robin coefficient");
      }
    }
    this->ExteriorDomain = exterior;
    this->WithSilhouettes = silhouettes;
    this->Other = std::make_shared<OtherSideSlot>();
    this->TwoSided = std::move(twoSided);
    this->AnyTwoSided =
      std::any_of(this->TwoSided.begin(), this->TwoSided.end(), [](std::uint8_t t) { return t != 0; });
    this->Robin = std::move(robin);
    this->AnyRobin = std::any_of(this->Robin.begin(), this->Robin.end(), [](double mu) { return mu > 0.0; });
    this->DirichletPart = hasD ? std::move(dirichlet) : nullptr;
    this->ReflectingPart = hasR ? std::move(reflecting) : nullptr;
    this->AnyFlux = false;
    for (int c = 0; hasR && c < this->ReflectingPart->Components(); ++c)
    {
      double lowest = 0.0, highest = 0.0;
      this->AnyFlux = this->AnyFlux || !this->ReflectingPart->ValueBounds(c, lowest, highest) ||
        lowest != 0.0 || highest != 0.0;
    }
    this->Normals.clear();
    this->Silhouette = SilhouetteTree<DIM>();
    this->Sampler = ReflectingBoundarySampler<DIM>();
    this->RobinBounds = RobinRadiusTree<DIM>();
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
      // The domain's side: the primitives as given, or reversed outside.
      std::vector<std::array<std::int64_t, DIM>> facing(p.begin(), p.end());
      if (exterior)
      {
        for (auto& prim : facing)
        {
          std::swap(prim[0], prim[1]);
        }
      }
      if (silhouettes)
      {
        this->Silhouette.Build(v, facing, this->TwoSided);
      }
      this->Sampler.Build(v, p);
      this->Normals.reserve(p.size());
      for (const auto& prim : facing)
      {
        this->Normals.push_back(OutwardUnitNormal<DIM>(v, prim));
      }
      box.Expand(this->ReflectingPart->BoundsMin());
      box.Expand(this->ReflectingPart->BoundsMax());
      if (this->AnyRobin)
      {
        this->RobinBounds.Build(this->Sampler, this->Robin, this->Normals);
      }
    }
    this->Box = box;
    this->ParityGap = 1e-9 * box.Diagonal();
    this->ParityDirections = ParityRayDirections<DIM>();
  }

  // Whether x is enclosed by the boundary, both parts together, by ray
  // parity (RayParity.h): walk on stars solves inside a closed boundary,
  // where the reflecting part's outward normals point away from x. True
  // everywhere when the Dirichlet part is not a mesh (no rays to count).
  bool Inside(const Vec<DIM>& x) const
  {
    if (this->DirichletPart && !this->DirichletPart->IsMesh())
    {
      return true;
    }
    if (!this->Box.Contains(x))
    {
      return false;
    }
    return MajorityParityVote<DIM>(this->ParityDirections, [&](const Vec<DIM>& d) {
      std::int64_t crossings = 0;
      for (const auto* part : { this->DirichletPart.get(), this->ReflectingPart.get() })
      {
        if (part)
        {
          const bool sheets = part == this->ReflectingPart.get() && this->AnyTwoSided;
          crossings += CountRayCrossings<DIM>(part->Hierarchy(), x, d, this->ParityGap,
            static_cast<std::int64_t>(part->NumberOfPrimitives()) + 1,
            sheets ? std::function<bool(std::int64_t)>(
                       [this](std::int64_t p) { return !this->IsTwoSided(p); })
                   : std::function<bool(std::int64_t)>());
        }
      }
      return crossings;
    });
  }

  bool HasDirichlet() const { return static_cast<bool>(this->DirichletPart); }
  bool HasReflecting() const { return static_cast<bool>(this->ReflectingPart); }
  const Boundary<DIM>& Dirichlet() const { return *this->DirichletPart; }
  const std::shared_ptr<const Boundary<DIM>>& SharedDirichlet() const { return this->DirichletPart; }
  const std::shared_ptr<const Boundary<DIM>>& SharedReflecting() const
  {
    return this->ReflectingPart;
  }
  const Boundary<DIM>& Reflecting() const { return *this->ReflectingPart; }
  const SilhouetteTree<DIM>& Silhouettes() const { return this->Silhouette; }
  const ReflectingBoundarySampler<DIM>& FluxSampler() const { return this->Sampler; }

  int Components() const
  {
    return this->DirichletPart ? this->DirichletPart->Components()
                               : this->ReflectingPart->Components();
  }

  // Whether the domain is the outside of the boundary (Set's `exterior`).
  bool IsExterior() const { return this->ExteriorDomain; }
  // The sign turning the reflecting part's value h on `primitive` into the
  // right-hand side along the domain's outward normal: a Neumann flux is
  // given along the mesh's normals (−1 outside), a Robin condition along
  // the domain's own normal (+1 on either side; Set).
  double FluxSign(std::int64_t primitive) const
  {
    return this->ExteriorDomain && !(this->RobinCoefficient(primitive) > 0.0) ? -1.0 : 1.0;
  }

  // The same boundary with the domain on its other side (the exterior of an
  // interior domain, and back): what walks from points outside the closed
  // boundary walk in (WalkOnStars.h, WalkSettings::MixedBothSides). Built
  // on first use, once, and shared by every copy of this boundary, so that
  // a problem whose points all lie inside never pays for it.
  const MixedBoundary& OtherSide() const
  {
    OtherSideSlot& slot = *this->Other;
    std::call_once(slot.Once, [&] {
      auto other = std::make_shared<MixedBoundary<DIM>>();
      other->Set(this->DirichletPart, this->ReflectingPart, this->Robin, this->WithSilhouettes,
        this->TwoSided, !this->ExteriorDomain);
      slot.Side = std::move(other);
    });
    return *slot.Side;
  }

  // Whether a primitive of the reflecting part is an insulating sheet.
  bool HasTwoSided() const { return this->AnyTwoSided; }
  bool IsTwoSided(std::int64_t primitive) const
  {
    return this->AnyTwoSided && this->TwoSided[static_cast<std::size_t>(primitive)] != 0;
  }

  // Whether the reflecting part has a flux h that is not 0 everywhere (or
  // one given by a function): with none, as on insulated walls, the flux
  // term (WoSt-3) is 0 and walks do not sample it.
  bool HasFlux() const { return this->AnyFlux; }

  // Whether some primitive has a Robin coefficient μ > 0.
  bool HasRobin() const { return this->AnyRobin; }
  double RobinCoefficient(std::int64_t primitive) const
  {
    return this->AnyRobin ? this->Robin[static_cast<std::size_t>(primitive)] : 0.0;
  }

  // The largest radius <= R at which every Robin point z of the star keeps
  // the walk's weight >= 0 for Δ (WoSt-7; RobinRadius.h).
  double RobinRadius(const Vec<DIM>& x, double R) const
  {
    return this->AnyRobin ? this->RobinBounds.Radius(this->Sampler, this->Robin, this->Normals, x, R)
                          : R;
  }

  // Unit outward normal of a primitive of the reflecting part, out of the
  // domain (into the object for an exterior domain).
  const Vec<DIM>& OutwardNormal(std::int64_t primitive) const
  {
    return this->Normals[static_cast<std::size_t>(primitive)];
  }

  const BoundingBox<DIM>& Bounds() const { return this->Box; }
  Vec<DIM> Center() const { return this->Box.Center(); }
  double Diagonal() const { return this->Box.Diagonal(); }

private:
  struct OtherSideSlot
  {
    std::once_flag Once;
    std::shared_ptr<const MixedBoundary<DIM>> Side;
  };

  std::shared_ptr<const Boundary<DIM>> DirichletPart;
  std::shared_ptr<const Boundary<DIM>> ReflectingPart;
  SilhouetteTree<DIM> Silhouette;
  ReflectingBoundarySampler<DIM> Sampler;
  RobinRadiusTree<DIM> RobinBounds;
  std::vector<Vec<DIM>> Normals;
  std::vector<double> Robin; // μ per reflecting primitive (empty: none)
  std::vector<std::uint8_t> TwoSided; // insulating sheets (empty: none)
  bool ExteriorDomain = false;
  bool WithSilhouettes = true;
  std::shared_ptr<OtherSideSlot> Other = std::make_shared<OtherSideSlot>();
  bool AnyTwoSided = false;
  double ParityGap = 0.0;
  std::array<Vec<DIM>, kParityRays> ParityDirections{};
  bool AnyRobin = false;
  bool AnyFlux = false;
  BoundingBox<DIM> Box;
};
} // namespace gridfree

#endif
