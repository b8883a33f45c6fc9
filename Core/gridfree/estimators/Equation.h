// What a walk-on-spheres estimator solves, and how: the equation, the
// biharmonic equation's strategy and the exterior problem's walk ending.
// The codes of Equation, BiharmonicStrategy (and of the source choices in
// sources/SourceSampling.h, sources/SourceOperator.h) are those of the VTK
// filters' properties, in the same order. A header of its own so that
// settings can name them without the estimators.
#ifndef GRIDFREE_ESTIMATORS_EQUATION_H
#define GRIDFREE_ESTIMATORS_EQUATION_H

namespace gridfree
{
enum class Equation
{
  Laplace,
  Poisson,
  ScreenedPoisson,
  Biharmonic,
  // ∇·(α∇u) − σu = f with varying α, σ, f (VaryingCoefficientWalk.h); the
  // coefficients come with the problem, not the settings.
  VaryingCoefficients
};

enum class BiharmonicStrategy
{
  TreeWalking, // Sec. 4.3: reuse the outer walk's boundary hit
  Nested       // Sec. 2.5: inner Laplace walks at every step
};

enum class ExteriorStrategy
{
  ExactReturn,    // survival probability = true return probability
  RussianRoulette // survival probability ρ_far/r per step, survivors reweighted
};

// How a screened walk's steps land (ScreenedGuide.h).
enum class ScreenedSteps
{
  Automatic, // guided where √c × the boundary's diagonal ≥ 10 and there is no source
  Uniform,   // uniformly on each sphere, the weight times C (paper Sec. 2.4)
  Guided     // always guided on a mesh, sources or not
};

// Whether walk on spheres' steps lean toward a narrow peak of the boundary
// data (PeakGuide.h; 3D meshes, Dirichlet problems).
enum class PeakSteps
{
  Automatic, // where the largest |g| is at least 10 times the mean |g| and there
             // is no source, no polynomial control variate, and no other guide
             // (nor Screened Steps set to Uniform)
  Uniform,   // never
  Guided     // wherever the data has a nonzero value (3D meshes)
};

} // namespace gridfree

#endif
