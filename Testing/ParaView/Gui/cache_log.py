"""The log cache_setup.py's observer writes (one line per execution of the
solver: `name=value` pairs), read by check_gui_cache.py and
check_gui_cache_refine.py: its first and last rows, checking that the
first answer came from a new cache (it holds just the walks it ran)."""


def first_and_last(path):
    rows = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            rows.append({k: float(v) for k, v in (item.split("=") for item in line.split())})
    assert len(rows) >= 2, rows
    first, last = rows[0], rows[-1]
    assert first["cache_walks"] > 0 and first["cache_walks"] == first["cache_walks_run"], first
    return first, last
