// The volume sources' gradients (VolumeSource::EvaluateGradient) as the
// solver builds them through gridfree::ConvertSource:
// (a) images with a rotated direction matrix and non-unit spacing: exact for
//     linear data, equal to differences of Evaluate for quadratic data inside
//     a voxel, and the same f as Evaluate;
// (b) unstructured tetrahedra (and triangles in 2D) holding linear data:
//     exact;
// (c) an expression, by central differences;
// (d) a two-component sum of an image and an expression;
// (e) zero value and gradient outside the sampled data.
#include "GridFreeSourceConversion.h"

#include "vtkCellType.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
int Failures = 0;

void Fail(const std::string& message)
{
  if (Failures < 40)
  {
    std::cerr << "FAILED: " << message << "\n";
  }
  ++Failures;
}

// |actual − expected| ≤ tolerance·max(|expected|, floor).
bool Near(double actual, double expected, double tolerance, double floor = 1.0)
{
  return std::isfinite(actual) &&
    std::abs(actual - expected) <= tolerance * std::max(std::abs(expected), floor);
}

template <int DIM>
std::string Describe(const char* what, const gridfree::Vec<DIM>& y, int component, int axis,
  double actual, double expected)
{
  std::ostringstream s;
  s.precision(17);
  s << what << " at (";
  for (int i = 0; i < DIM; ++i)
  {
    s << (i ? ", " : "") << y[i];
  }
  s << ") component " << component;
  if (axis >= 0)
  {
    s << " d/dx" << axis;
  }
  s << ": got " << actual << ", expected " << expected;
  return s.str();
}

// Builds the source with the solver's conversion and makes one instance.
template <int DIM>
std::unique_ptr<gridfree::VolumeSource<DIM>> MakeSource(vtkDataSet* data, vtkDataArray* array,
  const std::string& expression, int components, double planeZ, double lengthScale)
{
  gridfree::SourceSet<DIM> description;
  std::string reason;
  if (!gridfree::ConvertSource<DIM>(
        data, array, expression, components, planeZ, description, reason))
  {
    Fail("ConvertSource refused the input: " + reason);
    return nullptr;
  }
  if (!description.MakeVolume)
  {
    Fail("ConvertSource made no volume source");
    return nullptr;
  }
  return description.MakeVolume(lengthScale);
}

// Checks EvaluateGradient against an expected value and gradient
// (components × DIM, row-major), and that its f equals Evaluate's.
template <int DIM>
void CheckGradient(const char* what, gridfree::VolumeSource<DIM>& source,
  const gridfree::Vec<DIM>& y, int components, const std::vector<double>& expectedF,
  const std::vector<double>& expectedGradient, double valueTolerance, double gradientTolerance)
{
  std::vector<double> f(components, -1.0), evaluated(components, -2.0);
  std::vector<double> gradient(static_cast<std::size_t>(components) * DIM, -3.0);
  source.EvaluateGradient(y, components, f.data(), gradient.data());
  source.Evaluate(y, evaluated.data());
  double gradientNorm = 0.0;
  for (double g : expectedGradient)
  {
    gradientNorm = std::max(gradientNorm, std::abs(g));
  }
  for (int c = 0; c < components; ++c)
  {
    if (!(f[c] == evaluated[c]))
    {
      Fail(Describe<DIM>(what, y, c, -1, f[c], evaluated[c]) + " (EvaluateGradient vs Evaluate)");
    }
    if (!Near(f[c], expectedF[c], valueTolerance))
    {
      Fail(Describe<DIM>(what, y, c, -1, f[c], expectedF[c]) + " (value)");
    }
    for (int i = 0; i < DIM; ++i)
    {
      const double g = gradient[c * DIM + i];
      const double e = expectedGradient[c * DIM + i];
      // Relative to the gradient's size, so a zero entry is held to the same
      // absolute accuracy as the others.
      if (!Near(g, e, gradientTolerance, std::max(gradientNorm, 1e-300)))
      {
        Fail(Describe<DIM>(what, y, c, i, g, e) + " (gradient)");
      }
    }
  }
}

// Checks zero value and zero gradient.
template <int DIM>
void CheckZero(const char* what, gridfree::VolumeSource<DIM>& source, const gridfree::Vec<DIM>& y,
  int components)
{
  std::vector<double> zeros(static_cast<std::size_t>(components) * DIM, 0.0);
  CheckGradient<DIM>(what, source, y, components, std::vector<double>(components, 0.0), zeros,
    0.0, 0.0);
}

// Solves the DIM × DIM system M x = r (M row-major) by Gaussian elimination
// with partial pivoting.
template <int DIM>
std::array<double, DIM> Solve(std::array<double, DIM * DIM> m, std::array<double, DIM> r)
{
  for (int col = 0; col < DIM; ++col)
  {
    int pivot = col;
    for (int row = col + 1; row < DIM; ++row)
    {
      if (std::abs(m[row * DIM + col]) > std::abs(m[pivot * DIM + col]))
      {
        pivot = row;
      }
    }
    for (int k = 0; k < DIM; ++k)
    {
      std::swap(m[col * DIM + k], m[pivot * DIM + k]);
    }
    std::swap(r[col], r[pivot]);
    for (int row = col + 1; row < DIM; ++row)
    {
      const double factor = m[row * DIM + col] / m[col * DIM + col];
      for (int k = col; k < DIM; ++k)
      {
        m[row * DIM + k] -= factor * m[col * DIM + k];
      }
      r[row] -= factor * r[col];
    }
  }
  std::array<double, DIM> x{};
  for (int row = DIM - 1; row >= 0; --row)
  {
    double sum = r[row];
    for (int k = row + 1; k < DIM; ++k)
    {
      sum -= m[row * DIM + k] * x[k];
    }
    x[row] = sum / m[row * DIM + row];
  }
  return x;
}

// The world gradient a of f = c·index + b on an image: a·(step of index k in
// world coordinates) = c_k for every axis k, with the steps taken from VTK's
// own index-to-physical mapping (independent of the conversion's matrices).
template <int DIM>
std::array<double, DIM> WorldGradientOfIndexLinear(vtkImageData* image, const double c[3])
{
  double p0[3], pk[3];
  image->TransformContinuousIndexToPhysicalPoint(0.0, 0.0, 0.0, p0);
  std::array<double, DIM * DIM> m{};
  std::array<double, DIM> r{};
  for (int k = 0; k < DIM; ++k)
  {
    image->TransformContinuousIndexToPhysicalPoint(k == 0, k == 1, k == 2, pk);
    for (int j = 0; j < DIM; ++j)
    {
      m[k * DIM + j] = pk[j] - p0[j];
    }
    r[k] = c[k];
  }
  return Solve<DIM>(m, r);
}

// A rotation by `angle` about the axis (ux, uy, uz) (normalized here),
// row-major. Not symmetric for a generic axis, so its transpose differs.
std::array<double, 9> Rotation(double ux, double uy, double uz, double angle)
{
  const double n = std::sqrt(ux * ux + uy * uy + uz * uz);
  ux /= n;
  uy /= n;
  uz /= n;
  const double cs = std::cos(angle), sn = std::sin(angle), t = 1.0 - cs;
  return { t * ux * ux + cs, t * ux * uy - sn * uz, t * ux * uz + sn * uy, //
    t * ux * uy + sn * uz, t * uy * uy + cs, t * uy * uz - sn * ux,       //
    t * ux * uz - sn * uy, t * uy * uz + sn * ux, t * uz * uz + cs };
}

template <int DIM>
gridfree::Vec<DIM> ToVec(const double p[3])
{
  gridfree::Vec<DIM> v;
  for (int i = 0; i < DIM; ++i)
  {
    v[i] = p[i];
  }
  return v;
}

// (a) A 3D image, rotated and anisotropic, with an extent not starting at 0.
vtkSmartPointer<vtkImageData> MakeRotatedImage()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetExtent(2, 8, -1, 4, 0, 4);
  image->SetSpacing(0.3, 0.5, 0.7);
  image->SetOrigin(1.0, -2.0, 0.5);
  const std::array<double, 9> d = Rotation(1.0, 2.0, 3.0, 0.7);
  image->SetDirectionMatrix(d.data());
  return image;
}

// Fills a point array with `value(i, j, k, physical point)` per component.
// A random point strictly inside an image's extent: its continuous index
// and its world coordinates.
void RandomPointInImage(vtkImageData* image, std::mt19937_64& rng, double index[3], double p[3])
{
  int extent[6];
  image->GetExtent(extent);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 3; ++i)
  {
    index[i] = extent[2 * i] + 0.01 + (extent[2 * i + 1] - extent[2 * i] - 0.02) * unit(rng);
  }
  image->TransformContinuousIndexToPhysicalPoint(index, p);
}

template <class Function>
vtkSmartPointer<vtkDoubleArray> FillImage(
  vtkImageData* image, const char* name, int components, Function value)
{
  int extent[6];
  image->GetExtent(extent);
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(image->GetNumberOfPoints());
  vtkIdType id = 0;
  for (int k = extent[4]; k <= extent[5]; ++k)
  {
    for (int j = extent[2]; j <= extent[3]; ++j)
    {
      for (int i = extent[0]; i <= extent[1]; ++i, ++id)
      {
        double p[3];
        image->TransformIndexToPhysicalPoint(i, j, k, p);
        for (int c = 0; c < components; ++c)
        {
          array->SetComponent(id, c, value(c, i, j, k, p));
        }
      }
    }
  }
  image->GetPointData()->AddArray(array);
  return array;
}

void TestImageLinear3D(std::mt19937_64& rng)
{
  vtkSmartPointer<vtkImageData> image = MakeRotatedImage();
  {
    vtkMatrix3x3* d = image->GetDirectionMatrix();
    if (std::abs(d->GetElement(0, 1) - d->GetElement(1, 0)) < 0.1)
    {
      Fail("the test's direction matrix should be far from symmetric");
    }
  }
  // f = c·(i, j, k) + b: integer values at the voxels, exact in the float
  // copy the conversion keeps, so the gradient can be checked to 1e-9.
  const double c[3] = { 3.0, -2.0, 5.0 };
  const double b = 7.0;
  vtkSmartPointer<vtkDoubleArray> array =
    FillImage(image, "linear", 1, [&](int, int i, int j, int k, const double*) {
      return c[0] * i + c[1] * j + c[2] * k + b;
    });
  const std::array<double, 3> a = WorldGradientOfIndexLinear<3>(image, c);
  // The expected gradient reproduces f between voxels (sanity of the test).
  {
    double p[3], q[3];
    image->TransformIndexToPhysicalPoint(2, -1, 0, p);
    image->TransformIndexToPhysicalPoint(7, 3, 2, q);
    const double df = a[0] * (q[0] - p[0]) + a[1] * (q[1] - p[1]) + a[2] * (q[2] - p[2]);
    if (!Near(df, c[0] * 5 + c[1] * 4 + c[2] * 2, 1e-12))
    {
      Fail("the test's expected image gradient is inconsistent");
    }
  }

  auto source = MakeSource<3>(image, array, "", 1, 0.0, 10.0);
  if (!source)
  {
    return;
  }
  for (int n = 0; n < 200; ++n)
  {
    double index[3], p[3];
    RandomPointInImage(image, rng, index, p);
    const double expected = c[0] * index[0] + c[1] * index[1] + c[2] * index[2] + b;
    CheckGradient<3>("image linear", *source, ToVec<3>(p), 1, { expected },
      { a[0], a[1], a[2] }, 1e-9, 1e-9);
  }
  // Exactly on voxel corners and faces the gradient is still the linear one.
  int extent[6];
  image->GetExtent(extent);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 20; ++n)
  {
    const int i = extent[0] + static_cast<int>(unit(rng) * (extent[1] - extent[0] + 1) * 0.999);
    const int j = extent[2] + static_cast<int>(unit(rng) * (extent[3] - extent[2] + 1) * 0.999);
    const int k = extent[4] + static_cast<int>(unit(rng) * (extent[5] - extent[4] + 1) * 0.999);
    double p[3];
    image->TransformIndexToPhysicalPoint(i, j, k, p);
    CheckGradient<3>("image linear at a voxel corner", *source, ToVec<3>(p), 1,
      { c[0] * i + c[1] * j + c[2] * k + b }, { a[0], a[1], a[2] }, 1e-9, 1e-9);
  }

  // (e) Outside the image: zero value and gradient.
  // Continuous indices (the extent is [2, 8] × [-1, 4] × [0, 4]).
  const double outside[][3] = { { 1.5, 1.0, 2.0 }, { 8.5, 1.0, 2.0 }, { 5.0, -1.6, 2.0 },
    { 5.0, 4.4, 2.0 }, { 5.0, 1.0, -0.3 }, { 5.0, 1.0, 4.2 } };
  for (const auto& o : outside)
  {
    double p[3];
    image->TransformContinuousIndexToPhysicalPoint(o, p);
    CheckZero<3>("image outside", *source, ToVec<3>(p), 1);
  }
}

// Quadratic data: the trilinear interpolant's gradient inside a voxel must
// match central differences of Evaluate (the interpolant is smooth there).
void TestImageQuadratic3D(std::mt19937_64& rng)
{
  vtkSmartPointer<vtkImageData> image = MakeRotatedImage();
  vtkSmartPointer<vtkDoubleArray> array =
    FillImage(image, "quadratic", 1, [](int, int, int, int, const double* p) {
      return (p[0] - 1.0) * (p[0] - 1.0) + 2.0 * p[1] * p[2] - 0.5 * p[0] * p[2] + p[1];
    });
  auto source = MakeSource<3>(image, array, "", 1, 0.0, 10.0);
  if (!source)
  {
    return;
  }
  int extent[6];
  image->GetExtent(extent);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> voxel(0, 1 << 20);
  const double h = 1e-5; // well inside the voxel: fractions stay in [0.1, 0.9]
  for (int n = 0; n < 200; ++n)
  {
    double index[3], p[3];
    for (int i = 0; i < 3; ++i)
    {
      const int cells = extent[2 * i + 1] - extent[2 * i];
      index[i] = extent[2 * i] + voxel(rng) % cells + 0.1 + 0.8 * unit(rng);
    }
    image->TransformContinuousIndexToPhysicalPoint(index, p);
    const gridfree::Vec<3> y = ToVec<3>(p);
    double f0 = 0.0;
    source->Evaluate(y, &f0);
    std::vector<double> expected(3);
    for (int i = 0; i < 3; ++i)
    {
      gridfree::Vec<3> step = gridfree::Vec<3>::Zero();
      step[i] = h;
      double plus = 0.0, minus = 0.0;
      source->Evaluate(y + step, &plus);
      source->Evaluate(y - step, &minus);
      expected[i] = (plus - minus) / (2.0 * h);
    }
    CheckGradient<3>("image quadratic", *source, y, 1, { f0 }, expected, 0.0, 1e-6);
  }
}

// A 2D image in the plane z = 2 (direction: a rotation about z).
void TestImageLinear2D(std::mt19937_64& rng)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(6, 5, 1);
  image->SetSpacing(0.25, 0.75, 1.0);
  image->SetOrigin(0.5, -1.0, 2.0);
  const std::array<double, 9> d = Rotation(0.0, 0.0, 1.0, 0.4);
  image->SetDirectionMatrix(d.data());
  const double c[3] = { 3.0, -2.0, 0.0 };
  vtkSmartPointer<vtkDoubleArray> array =
    FillImage(image, "linear", 1, [&](int, int i, int j, int, const double*) {
      return c[0] * i + c[1] * j + 1.0;
    });
  const std::array<double, 2> a = WorldGradientOfIndexLinear<2>(image, c);
  auto source = MakeSource<2>(image, array, "", 1, 2.0, 10.0);
  if (!source)
  {
    return;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 100; ++n)
  {
    const double index[3] = { 0.01 + 4.98 * unit(rng), 0.01 + 3.98 * unit(rng), 0.0 };
    double p[3];
    image->TransformContinuousIndexToPhysicalPoint(index, p);
    CheckGradient<2>("2D image linear", *source, ToVec<2>(p), 1,
      { c[0] * index[0] + c[1] * index[1] + 1.0 }, { a[0], a[1] }, 1e-9, 1e-9);
  }
  double p[3];
  image->TransformContinuousIndexToPhysicalPoint(-0.3, 2.0, 0.0, p);
  CheckZero<2>("2D image outside", *source, ToVec<2>(p), 1);
  image->TransformContinuousIndexToPhysicalPoint(2.0, 4.3, 0.0, p);
  CheckZero<2>("2D image outside", *source, ToVec<2>(p), 1);
}

// (b) An image split into simplices (tetrahedra, or triangles for a flat
// image) with its points moved by multiples of 1/64, holding
// f = a·x + b (exact in float for such coordinates).
vtkSmartPointer<vtkUnstructuredGrid> MakeSimplices(
  int nx, int ny, int nz, double z0, std::mt19937_64& rng)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(nx, ny, nz);
  image->SetSpacing(0.5, 0.5, 0.5);
  image->SetOrigin(-1.0, 0.0, z0);
  vtkNew<vtkDataSetTriangleFilter> triangulate;
  triangulate->SetInputData(image);
  triangulate->Update();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->DeepCopy(triangulate->GetOutput());
  std::uniform_int_distribution<int> jitter(-2, 2);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(grid->GetNumberOfPoints());
  for (vtkIdType id = 0; id < grid->GetNumberOfPoints(); ++id)
  {
    double p[3];
    grid->GetPoint(id, p);
    p[0] += jitter(rng) / 64.0;
    p[1] += jitter(rng) / 64.0;
    if (nz > 1)
    {
      p[2] += jitter(rng) / 64.0;
    }
    points->SetPoint(id, p);
  }
  grid->SetPoints(points);
  return grid;
}

void TestSimplicesLinear(std::mt19937_64& rng)
{
  const double a[3] = { 1.5, -2.25, 0.75 };
  const double b = 0.5;
  auto linear = [&](const double* p) { return a[0] * p[0] + a[1] * p[1] + a[2] * p[2] + b; };
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // 3D: tetrahedra over [-1, 1.5] × [0, 2] × [0.5, 2].
  {
    vtkSmartPointer<vtkUnstructuredGrid> grid = MakeSimplices(6, 5, 4, 0.5, rng);
    for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell)
    {
      if (grid->GetCellType(cell) != VTK_TETRA)
      {
        Fail("the triangulated grid should hold tetrahedra only");
        break;
      }
    }
    vtkNew<vtkDoubleArray> array;
    array->SetName("linear");
    array->SetNumberOfTuples(grid->GetNumberOfPoints());
    for (vtkIdType id = 0; id < grid->GetNumberOfPoints(); ++id)
    {
      array->SetValue(id, linear(grid->GetPoint(id)));
    }
    grid->GetPointData()->AddArray(array);
    auto source = MakeSource<3>(grid, array, "", 1, 0.0, 10.0);
    if (source)
    {
      for (int n = 0; n < 200; ++n)
      {
        const double p[3] = { -0.9 + 2.3 * unit(rng), 0.1 + 1.8 * unit(rng),
          0.6 + 1.3 * unit(rng) };
        CheckGradient<3>("tetrahedra linear", *source, ToVec<3>(p), 1, { linear(p) },
          { a[0], a[1], a[2] }, 1e-9, 1e-9);
      }
      const double outside[][3] = { { -1.2, 1.0, 1.0 }, { 1.7, 1.0, 1.0 }, { 0.0, -0.2, 1.0 },
        { 0.0, 2.2, 1.0 }, { 0.0, 1.0, 0.3 }, { 0.0, 1.0, 2.2 } };
      for (const auto& o : outside)
      {
        CheckZero<3>("tetrahedra outside", *source, ToVec<3>(o), 1);
      }
    }
  }

  // 2D: triangles in the plane z = 1.5; only the x and y derivatives.
  {
    vtkSmartPointer<vtkUnstructuredGrid> grid = MakeSimplices(6, 5, 1, 1.5, rng);
    vtkNew<vtkDoubleArray> array;
    array->SetName("linear");
    array->SetNumberOfTuples(grid->GetNumberOfPoints());
    for (vtkIdType id = 0; id < grid->GetNumberOfPoints(); ++id)
    {
      array->SetValue(id, linear(grid->GetPoint(id)));
    }
    grid->GetPointData()->AddArray(array);
    auto source = MakeSource<2>(grid, array, "", 1, 1.5, 10.0);
    if (source)
    {
      for (int n = 0; n < 100; ++n)
      {
        const double p[3] = { -0.9 + 2.3 * unit(rng), 0.1 + 1.8 * unit(rng), 1.5 };
        CheckGradient<2>("triangles linear", *source, ToVec<2>(p), 1, { linear(p) },
          { a[0], a[1] }, 1e-9, 1e-9);
      }
      const double outside[3] = { 1.7, 1.0, 1.5 };
      CheckZero<2>("triangles outside", *source, ToVec<2>(outside), 1);
    }
  }
}

// (c) An expression, differentiated by central differences.
void TestExpression(std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
  for (double lengthScale : { 2.0, 0.0 }) // 0: the default, point-relative step
  {
    auto source = MakeSource<3>(nullptr, nullptr, "x*x + 3*y - z", 1, 0.0, lengthScale);
    if (!source)
    {
      return;
    }
    for (int n = 0; n < 100; ++n)
    {
      const double p[3] = { coordinate(rng), coordinate(rng), coordinate(rng) };
      CheckGradient<3>("expression", *source, ToVec<3>(p), 1,
        { p[0] * p[0] + 3 * p[1] - p[2] }, { 2 * p[0], 3.0, -1.0 }, 1e-12, 1e-6);
    }
  }
  // In 2D the expression is sampled in the plane z = planeZ.
  auto flat = MakeSource<2>(nullptr, nullptr, "x*x + 3*y - z", 1, 0.25, 2.0);
  if (flat)
  {
    for (int n = 0; n < 50; ++n)
    {
      const double p[3] = { coordinate(rng), coordinate(rng), 0.25 };
      CheckGradient<2>("2D expression", *flat, ToVec<2>(p), 1,
        { p[0] * p[0] + 3 * p[1] - 0.25 }, { 2 * p[0], 3.0 }, 1e-12, 1e-6);
    }
  }
  // The length scale sets the step: for x³ central differences give
  // 3x² + h², so a large scale (h = 1e-5·1000 = 0.01) shows in the result.
  auto cubic = MakeSource<3>(nullptr, nullptr, "x*x*x", 1, 0.0, 1000.0);
  if (cubic)
  {
    const double h = 1e-5 * 1000.0;
    const gridfree::Vec<3> y(1.5, 0.0, 0.0);
    CheckGradient<3>("expression step from the length scale", *cubic, y, 1, { 1.5 * 1.5 * 1.5 },
      { 3 * 1.5 * 1.5 + h * h, 0.0, 0.0 }, 1e-12, 1e-9);
  }
}

// (d) Two components: an image with a two-component array plus an expression
// (which applies to both components); (e) outside the image only the
// expression remains.
void TestSum(std::mt19937_64& rng)
{
  vtkSmartPointer<vtkImageData> image = MakeRotatedImage();
  const double c[2][3] = { { 3.0, -2.0, 5.0 }, { -1.0, 4.0, 2.0 } };
  const double b[2] = { 7.0, -3.0 };
  vtkSmartPointer<vtkDoubleArray> array =
    FillImage(image, "pair", 2, [&](int comp, int i, int j, int k, const double*) {
      return c[comp][0] * i + c[comp][1] * j + c[comp][2] * k + b[comp];
    });
  const std::array<double, 3> a0 = WorldGradientOfIndexLinear<3>(image, c[0]);
  const std::array<double, 3> a1 = WorldGradientOfIndexLinear<3>(image, c[1]);
  auto source = MakeSource<3>(image, array, "x*x + 3*y - z", 2, 0.0, 10.0);
  if (!source)
  {
    return;
  }
  for (int n = 0; n < 100; ++n)
  {
    double index[3], p[3];
    RandomPointInImage(image, rng, index, p);
    const double e = p[0] * p[0] + 3 * p[1] - p[2];
    const double ge[3] = { 2 * p[0], 3.0, -1.0 };
    const double f0 = c[0][0] * index[0] + c[0][1] * index[1] + c[0][2] * index[2] + b[0] + e;
    const double f1 = c[1][0] * index[0] + c[1][1] * index[1] + c[1][2] * index[2] + b[1] + e;
    CheckGradient<3>("sum", *source, ToVec<3>(p), 2, { f0, f1 },
      { a0[0] + ge[0], a0[1] + ge[1], a0[2] + ge[2], a1[0] + ge[0], a1[1] + ge[1],
        a1[2] + ge[2] },
      1e-9, 1e-6);
  }
  double p[3];
  image->TransformContinuousIndexToPhysicalPoint(-0.5, 1.0, 1.0, p);
  const double e = p[0] * p[0] + 3 * p[1] - p[2];
  CheckGradient<3>("sum outside the image", *source, ToVec<3>(p), 2, { e, e },
    { 2 * p[0], 3.0, -1.0, 2 * p[0], 3.0, -1.0 }, 1e-12, 1e-6);
}
} // namespace

int TestSourceGradients(int, char*[])
{
  std::mt19937_64 rng(20240611);
  TestImageLinear3D(rng);
  TestImageQuadratic3D(rng);
  TestImageLinear2D(rng);
  TestSimplicesLinear(rng);
  TestExpression(rng);
  TestSum(rng);
  if (Failures > 0)
  {
    std::cerr << Failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "All source gradient checks passed\n";
  return EXIT_SUCCESS;
}
