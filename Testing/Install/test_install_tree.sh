#!/usr/bin/env bash
# The installed package, used as a C++ and a Python user would use it:
#   1. `cmake --install` the build into a fresh prefix;
#   2. configure, build and run the documentation's C++ example
#      (Documentation/Examples/Cxx) on its own, with find_package(GridFree)
#      and only -DCMAKE_PREFIX_PATH=<prefix>; it must link the installed
#      library, not the build tree's, and pass its own accuracy check;
#   3. the same for the core-only example (Documentation/Examples/Core),
#      with find_package(GridFree COMPONENTS Core): no VTK or ParaView may
#      appear in its compile commands, its link line or its libraries;
#   4. `import gridfree` from /usr/bin/python3 and pvpython with PYTHONPATH
#      (and PV_PLUGIN_PATH) pointing into the prefix only, and solve.
# Usage: test_install_tree.sh <build dir> <source dir> <work dir>
set -euo pipefail
build="$1" source="$2" work="$3"
prefix="$work/prefix"
rm -rf "$work"
mkdir -p "$work"

echo "== cmake --install into $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
test -f "$prefix/lib/cmake/GridFree/GridFreeConfig.cmake"

echo "== the C++ example against the install tree"
cmake -S "$source/Documentation/Examples/Cxx" -B "$work/example" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" >"$work/example-configure.log"
cmake --build "$work/example" >"$work/example-build.log"
library=$(ldd "$work/example/SolveOnPlane" | awk '/libGridFreeFilters/ {print $3}')
echo "SolveOnPlane links $library"
case "$library" in
  "$prefix"/*) ;;
  *) echo "FAIL: the example does not link the installed library"; exit 1 ;;
esac
"$work/example/SolveOnPlane"

echo "== the core-only example against the install tree"
test -f "$prefix/include/gridfree/boundary/Boundary.h"
test -f "$prefix/lib/cmake/GridFree/GridFreeCore-targets.cmake"
cmake -S "$source/Documentation/Examples/Core" -B "$work/core-example" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$work/core-example-configure.log"
cmake --build "$work/core-example" >"$work/core-example-build.log"
if grep -iE 'vtk|paraview' "$work/core-example/compile_commands.json" \
    "$work/core-example/CMakeFiles/LaplaceOnMesh.dir/link.txt"; then
  echo "FAIL: VTK or ParaView in the core-only example's compile or link commands"
  exit 1
fi
if grep -iE 'paraview|vtk' "$work/core-example/CMakeCache.txt" | grep -v '^//' | grep -iE '_DIR:'; then
  echo "FAIL: find_package(GridFree COMPONENTS Core) looked for ParaView or VTK"
  exit 1
fi
if ldd "$work/core-example/LaplaceOnMesh" | grep -iE 'vtk|paraview'; then
  echo "FAIL: the core-only example loads VTK or ParaView libraries"
  exit 1
fi
# The core's headers come from the prefix, not from the source tree.
grep -q "$prefix/include" "$work/core-example/compile_commands.json"
if grep -q "$source/Core" "$work/core-example/compile_commands.json"; then
  echo "FAIL: the core-only example reads the core from the source tree"
  exit 1
fi
"$work/core-example/LaplaceOnMesh" "$source/Data/spot.obj" 1024

echo "== Python from the install tree"
site="$prefix/lib/python3.11/site-packages"
plugins="$prefix/lib/paraview-5.11/plugins/GridFree"
check_module='import gridfree, sys; f = gridfree.__file__; print("gridfree from", f); sys.exit(0 if f.startswith(sys.argv[1]) else 1)'
env -u PV_PLUGIN_PATH PYTHONPATH="$site" /usr/bin/python3 -c "$check_module" "$prefix"
env -u PV_PLUGIN_PATH PYTHONPATH="$site" /usr/bin/python3 - <<'PY'
import gridfree
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
sphere = vtkSphereSource()
sphere.Update()
solver = gridfree.vtkWalkOnSpheresSolver()
solver.SetBoundaryData(sphere.GetOutput())
solver.SetInputArrayToProcess(0, 0, 0, 0, "Normals")
plane = vtkPlaneSource()
solver.SetProbeConnection(plane.GetOutputPort())
solver.SetWalksPerPoint(16)
solver.Update()
# The plane has Normals of its own, which it keeps: the solution is Normals_Solution.
assert solver.GetOutput().GetPointData().GetArray("Normals_Solution_Variance") is not None
print("python3: solved", solver.GetOutput().GetNumberOfPoints(), "points")
PY
PYTHONPATH="$site" PV_PLUGIN_PATH="$plugins" pvpython -c "$check_module" "$prefix"
PYTHONPATH="$site" PV_PLUGIN_PATH="$plugins" pvpython "$source/Testing/ParaView/test_pvpython_import.py"
echo "ok"
