"""Checks the log cache_setup.py's observer wrote while cache_moved_slice.xml
moved the slice in the GUI: the solver answered at z = 0, then at z = 1.5,
both times mostly from the Sphere Cache, and the second answer came from
the same cache. How it knows: the cache's field data CacheWalks (walks held
by all its spheres) after the move equals the walks held before plus the
walks run for the move (CacheWalksRun, the spheres the new slice needed
that the first did not); a cache built anew would hold only the walks run
for the move.

    python3 check_gui_cache.py solver_log.txt"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cache_log import first_and_last  # noqa: E402

first, last = first_and_last(sys.argv[1])
assert first["z"] == 0.0 and last["z"] == 1.5, (first, last)
assert first["points_from_cache"] > 50 and last["points_from_cache"] > 50, (first, last)
kept = last["cache_walks"] - last["cache_walks_run"]
assert kept == first["cache_walks"], (first, last)
print("ok: the moved slice was answered from the same cache: %d walks kept, %d run for the move "
      "(%d run for the first slice)" % (kept, last["cache_walks_run"], first["cache_walks_run"]))
