#!/usr/bin/env bash
# The installed package, used as a C++ and a Python user would use it:
#   1. `cmake --install` the build into a fresh prefix;
#   2. configure, build and run the documentation's C++ example
#      (Documentation/Examples/Cxx) on its own, with find_package(GridFree)
#      and only -DCMAKE_PREFIX_PATH=<prefix>; it must link the installed
#      library, not the build tree's, and pass its own accuracy check;
#   3. `import gridfree` from /usr/bin/python3 and pvpython with PYTHONPATH
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
assert solver.GetOutput().GetPointData().GetArray("Normals_Variance") is not None
print("python3: solved", solver.GetOutput().GetNumberOfPoints(), "points")
PY
PYTHONPATH="$site" PV_PLUGIN_PATH="$plugins" pvpython -c "$check_module" "$prefix"
PYTHONPATH="$site" PV_PLUGIN_PATH="$plugins" pvpython "$source/Testing/ParaView/test_pvpython_import.py"
echo "ok"
