# Unity batches for the core's test executable (the main build's and the
# sanitizer builds'): the test files instantiate the same core templates
# (estimators, hierarchies, samplers), which a batch of six files compiles
# once instead of six times. Files whose file-local names (kInf, Points,
# Walks, a Field of their own) clash with another file's compile on their own,
# and so do files that instantiate none of those templates (a batch would
# only make them recompile with their neighbours).
function(gridfree_unity_batches target test_dir)
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 6)
  foreach (file IN ITEMS geometry/TestBvh geometry/TestBvhRays sources/TestConcentratedSources
      applications/TestCrossField implicit/TestCsgFunctionsCachedBounds
      estimators/TestDerivativeWalkOnSpheres estimators/TestWalkOnSpheresExterior
      estimators/TestWalkOnSpheresPoisson cache/TestScreenedBallSeries
      estimators/TestVaryingCoefficientWalk coefficients/TestVaryingCoefficients
      coefficients/TestScreeningMajorant coefficients/TestImageCoefficients
      estimators/TestVaryingCoefficientWalkCtReference)
    set_source_files_properties("${test_dir}/${file}.cxx" TARGET_DIRECTORY ${target}
      PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endforeach ()
endfunction()
