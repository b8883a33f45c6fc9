// How a walk samples the volume source term in each ball (paper Sec. 4.2;
// SourceTerms.h).
#ifndef GRIDFREE_SOURCES_SOURCE_SAMPLING_H
#define GRIDFREE_SOURCES_SOURCE_SAMPLING_H

namespace gridfree
{
// How the volume term ∫_B f G is sampled.
enum class SourceSampling
{
  Uniform,            // y ~ U(B): weight |B| G(x, y)
  GreensFunction,     // y ~ G / ∫G: weight ∫G (App. B samplers)
  MultipleImportance, // one sample of each, balance heuristic (Veach & Guibas 1995)
  SourceDensity,      // y ~ G / ∫G and y ~ |f| (SourceDensityMap.h), balance heuristic
  Automatic           // SourceDensity for a narrow volume source, else GreensFunction
                      // (Problem decides from |f|; an estimator made without a
                      // Problem takes GreensFunction)
};

} // namespace gridfree

#endif
