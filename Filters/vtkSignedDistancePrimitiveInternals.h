// Shared by the vtkSignedDistance* classes and GridFreeImplicitBoundary.cxx:
// parameter checks that mirror the core constructors' (so EvaluateFunction
// can refuse invalid parameters without an exception per point), and the
// core function of each primitive. Private to the GridFree::Filters module:
// it brings in Eigen and the core, which the public headers must not.
#ifndef vtkSignedDistancePrimitiveInternals_h
#define vtkSignedDistancePrimitiveInternals_h

#include <gridfree/implicit/SignedDistanceFunctions.h>

#include <cmath>
#include <limits>
#include <memory>

class vtkSignedDistanceBox;
class vtkSignedDistanceCapsule;
class vtkSignedDistanceCylinder;
class vtkSignedDistancePlane;
class vtkSignedDistanceRoundedBox;
class vtkSignedDistanceSphere;
class vtkSignedDistanceTorus;

namespace gridfree
{
namespace primitive
{
inline Vec3 ToVec3(const double v[3])
{
  return Vec3(v[0], v[1], v[2]);
}

inline bool IsFinite3(const double v[3])
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

inline bool IsPositive(double value)
{
  return value > 0.0 && std::isfinite(value);
}

// What detail::RequireDirection accepts: finite, with a positive finite
// (stable) norm.
inline bool IsDirection(const double v[3])
{
  if (!IsFinite3(v))
  {
    return false;
  }
  const double length = ToVec3(v).stableNorm();
  return length > 0.0 && std::isfinite(length);
}

inline double NaN()
{
  return std::numeric_limits<double>::quiet_NaN();
}

inline void StoreGradient(const Vec3& g, double out[3])
{
  out[0] = g[0];
  out[1] = g[1];
  out[2] = g[2];
}

inline void StoreNaN(double out[3])
{
  out[0] = out[1] = out[2] = NaN();
}

// EvaluateFunction of every primitive: NaN while `problem` (its
// GetParameterProblem()) is set, else the value of the core function that
// makeCore() builds from the current parameters (only built when valid).
template <class MakeCore>
double ValueOrNaN(const char* problem, const MakeCore& makeCore, const double x[3])
{
  return problem ? NaN() : makeCore().Value(ToVec3(x));
}

// EvaluateGradient of every primitive, likewise.
template <class MakeCore>
void GradientOrNaN(const char* problem, const MakeCore& makeCore, const double x[3], double g[3])
{
  if (problem)
  {
    StoreNaN(g);
    return;
  }
  StoreGradient(makeCore().Gradient(ToVec3(x)), g);
}

inline void StoreBounds(const BoundingBox<3>& box, double bounds[6])
{
  for (int k = 0; k < 3; ++k)
  {
    bounds[2 * k] = box.Min[k];
    bounds[2 * k + 1] = box.Max[k];
  }
}
} // namespace primitive

// The core function with the primitive's current parameters, for the
// solver. The parameters must be valid (HasValidParameters()); the core
// constructors throw std::invalid_argument otherwise.
using SharedDistance3 = std::shared_ptr<const SignedDistanceFunction<3>>;
SharedDistance3 MakeCoreDistance(vtkSignedDistanceSphere* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistanceBox* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistanceRoundedBox* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistanceTorus* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistanceCylinder* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistanceCapsule* primitive);
SharedDistance3 MakeCoreDistance(vtkSignedDistancePlane* primitive);
} // namespace gridfree

#endif
