"""Checks the log cache_setup.py's observer wrote while cache_refine.xml
pressed Refine on the solver with the Sphere Cache estimator: the second
execution answered the same slice from the same spheres, each continued
from 32 to 64 walks. How it knows: the walks run by the refine
(CacheWalksRun) equal the walks the first answer held (CacheWalks: the
spheres at 32 walks each), and the cache then holds twice as many; a new
cache would have run all 64 per sphere, and a cache left as it was none.

    python3 check_gui_cache_refine.py solver_log.txt"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cache_log import first_and_last  # noqa: E402

first, last = first_and_last(sys.argv[1])
assert first["z"] == 0.0 and last["z"] == 0.0, (first, last)
assert first["points_from_cache"] > 50 and last["points_from_cache"] == first["points_from_cache"]
assert last["cache_walks_run"] == first["cache_walks"], (first, last)
assert last["cache_walks"] == 2 * first["cache_walks"], (first, last)
print("ok: Refine continued the spheres' walks: %d held, %d run by the refine"
      % (last["cache_walks"], last["cache_walks_run"]))
