// The BVH on the CT-derived meshes this project is made for, against brute
// force: the bundled closed skin surface, and a raw bone isosurface of the
// bundled CT volume turned into a triangle soup (every triangle with its own
// three vertices, as raw marching-cubes output often is). Queries uniform in
// the box, near the surface (down to exactly on a vertex) and far away; every
// instruction set the CPU supports gives the same bits as the baseline.
// Walk on stars' silhouette tree on the same meshes, against a loop over
// every silhouette candidate.
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/stars/SilhouetteTree.h>

#include "vtkCellArray.h"
#include "vtkFlyingEdges3D.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkMetaImageReader.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataReader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
using gridfree::Bvh;
using gridfree::Vec3;

struct Triangles
{
  std::vector<Vec3> Vertices;
  std::vector<Bvh<3>::Primitive> Faces;
};

// The polygons of a surface as triangles (fans), optionally as a soup.
Triangles FromPolyData(vtkPolyData* poly, bool soup)
{
  Triangles t;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
  {
    double p[3];
    poly->GetPoint(i, p);
    t.Vertices.emplace_back(p[0], p[1], p[2]);
  }
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = poly->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
  {
    for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k)
    {
      t.Faces.push_back({ ids->GetId(0), ids->GetId(k), ids->GetId(k + 1) });
    }
  }
  if (soup)
  {
    Triangles s;
    for (const auto& f : t.Faces)
    {
      const auto base = static_cast<std::int64_t>(s.Vertices.size());
      for (int k = 0; k < 3; ++k)
      {
        s.Vertices.push_back(t.Vertices[f[k]]);
      }
      s.Faces.push_back({ base, base + 1, base + 2 });
    }
    return s;
  }
  return t;
}

double BruteForce(const Triangles& t, const Vec3& x)
{
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : t.Faces)
  {
    best = std::min(best,
      gridfree::SquaredDistanceToTriangle(x, t.Vertices[f[0]], t.Vertices[f[1]], t.Vertices[f[2]]));
  }
  return best;
}

void CheckAgainstBruteForce(const Triangles& t, int perKind, unsigned seed)
{
  ASSERT_GT(t.Faces.size(), 10000u);
  Bvh<3> bvh;
  bvh.Build(t.Vertices, t.Faces);
  ASSERT_TRUE(bvh.Validate());
  const auto& box = bvh.Bounds();
  const double diagonal = box.Diagonal();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gauss;
  auto direction = [&]() { return Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized(); };
  std::vector<Vec3> queries;
  for (int i = 0; i < perKind; ++i)
  {
    queries.push_back(box.Min + (box.Max - box.Min).cwiseProduct(Vec3(u(rng), u(rng), u(rng))));
    const auto& f = t.Faces[rng() % t.Faces.size()];
    const Vec3 onSurface = (i % 3 == 0) ? t.Vertices[f[0]]
                                         : (t.Vertices[f[0]] + t.Vertices[f[1]] + t.Vertices[f[2]]) / 3.0;
    const double offset = (i % 3 == 0) ? 0.0 : diagonal * std::pow(10.0, -9.0 + 7.0 * u(rng));
    queries.push_back(onSurface + offset * direction());
    queries.push_back(box.Center() + diagonal * (1.0 + 10.0 * u(rng)) * direction());
  }
  // The baseline instruction set against brute force; then every level the
  // CPU supports against the baseline, bit for bit (SimdDispatch.h).
  bvh.SetSimdLevel(gridfree::SimdLevel::Sse2);
  std::vector<double> baseline;
  for (const Vec3& x : queries)
  {
    const double ref2 = BruteForce(t, x);
    const double d2 = bvh.SquaredDistance(x);
    baseline.push_back(d2);
    // The same kernels: equal up to their last-bit rounding.
    ASSERT_NEAR(std::sqrt(d2), std::sqrt(ref2), 1e-12 * std::sqrt(ref2) + 1e-14 * diagonal)
      << "query " << x.transpose();
    const auto r = bvh.ClosestPoint(x);
    ASSERT_GE(r.primitive, 0);
    const auto& f = t.Faces[static_cast<std::size_t>(r.primitive)];
    const double own =
      gridfree::SquaredDistanceToTriangle(x, t.Vertices[f[0]], t.Vertices[f[1]], t.Vertices[f[2]]);
    EXPECT_NEAR(std::sqrt(own), std::sqrt(ref2), 1e-12 * std::sqrt(ref2) + 1e-14 * diagonal);
    baseline.push_back(r.distance);
    baseline.insert(baseline.end(), r.point.data(), r.point.data() + 3);
    baseline.push_back(static_cast<double>(r.primitive));
  }
  for (const auto level : { gridfree::SimdLevel::Avx2, gridfree::SimdLevel::Avx512 })
  {
    if (bvh.SetSimdLevel(level) != level)
    {
      continue; // not on this CPU
    }
    std::vector<double> answers;
    for (const Vec3& x : queries)
    {
      answers.push_back(bvh.SquaredDistance(x));
      const auto r = bvh.ClosestPoint(x);
      answers.push_back(r.distance);
      answers.insert(answers.end(), r.point.data(), r.point.data() + 3);
      answers.push_back(static_cast<double>(r.primitive));
    }
    EXPECT_TRUE(answers == baseline) << gridfree::SimdLevelName(level) << " differs from sse2";
  }
}
// The bundled closed skin surface.
vtkSmartPointer<vtkPolyData> SkinSurface()
{
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(GRIDFREE_DATA_DIR "/headsq_skin_iso500_closed.vtp");
  reader->Update();
  return reader->GetOutput();
}

// A raw bone isosurface of the bundled CT volume (marching-cubes output).
vtkSmartPointer<vtkPolyData> BoneIsosurface()
{
  vtkNew<vtkMetaImageReader> reader;
  reader->SetFileName(GRIDFREE_DATA_DIR "/headsq_headCT.mhd");
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputConnection(reader->GetOutputPort());
  contour->SetValue(0, 1150.0);
  contour->ComputeNormalsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  return contour->GetOutput();
}

// The closest silhouette from the tree equals a loop over its candidates,
// bit for bit, at points in the box, near and on the surface; the surface
// as given and turned inside out (the domain on the other side).
void CheckSilhouettesAgainstBruteForce(Triangles t, int queries, unsigned seed)
{
  for (int flip = 0; flip < 2; ++flip)
  {
    gridfree::SilhouetteTree<3> tree;
    tree.Build(t.Vertices, t.Faces);
    ASSERT_GT(tree.NumberOfCandidates(), 100u);
    gridfree::BoundingBox<3> bounds;
    for (const Vec3& v : t.Vertices)
    {
      bounds.Expand(v);
    }
    std::mt19937_64 rng(seed + flip);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int found = 0;
    for (int q = 0; q < queries; ++q)
    {
      const auto& f = t.Faces[rng() % t.Faces.size()];
      const Vec3 x = q % 2 ? Vec3(bounds.Min + bounds.Extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng))))
                           : Vec3((t.Vertices[f[0]] + t.Vertices[f[1]] + t.Vertices[f[2]]) / 3.0 +
                               bounds.Diagonal() * 0.01 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
      const double rMax = q % 3 ? std::numeric_limits<double>::infinity() : bounds.Diagonal() * u(rng);
      double best = rMax, best2 = rMax * rMax;
      for (const auto& c : tree.CandidateList())
      {
        const Vec3 p = c.ClosestPoint(x);
        const double d2 = (x - p).squaredNorm();
        if (d2 < best2 && gridfree::IsSilhouette(c, x, p, std::sqrt(d2), tree.OnCandidateTolerance()))
        {
          best2 = d2;
          best = std::sqrt(d2);
        }
      }
      ASSERT_EQ(tree.ClosestDistance(x, rMax), best) << "query " << q;
      found += best < rMax ? 1 : 0;
    }
    EXPECT_GT(found, queries / 4);
    for (auto& face : t.Faces)
    {
      std::swap(face[1], face[2]);
    }
  }
}
} // namespace

TEST(BvhOnCtMeshes, SilhouettesOfTheClosedSkinSurface)
{
  vtkSmartPointer<vtkPolyData> skin = SkinSurface();
  ASSERT_GT(skin->GetNumberOfPolys(), 0) << "cannot read the skin surface";
  CheckSilhouettesAgainstBruteForce(FromPolyData(skin, false), 200, 3);
}

TEST(BvhOnCtMeshes, SilhouettesOfTheBoneIsosurfaceAndItsSoup)
{
  vtkSmartPointer<vtkPolyData> bone = BoneIsosurface();
  CheckSilhouettesAgainstBruteForce(FromPolyData(bone, false), 60, 4);
  CheckSilhouettesAgainstBruteForce(FromPolyData(bone, true), 30, 5);
}

TEST(BvhOnCtMeshes, ClosedSkinSurface)
{
  vtkSmartPointer<vtkPolyData> skin = SkinSurface();
  ASSERT_GT(skin->GetNumberOfPolys(), 0) << "cannot read the skin surface";
  CheckAgainstBruteForce(FromPolyData(skin, false), 60, 1);
}

TEST(BvhOnCtMeshes, RawBoneIsosurfaceSoup)
{
  vtkSmartPointer<vtkPolyData> bone = BoneIsosurface();
  CheckAgainstBruteForce(FromPolyData(bone, true), 60, 2);
}
