"""Error against time, pointwise walks, the sphere cache and (with --peers)
zombie's boundary value caching, from the tables `./gridfree bench --cache`
prints (one file per shape), as a picture:

    ./gridfree bench --cache --peers > icosphere.txt
    ./gridfree bench --cache --peers --shape bumpy > bumpy.txt
    /usr/bin/python3 plot_cache_errors.py icosphere.txt bumpy.txt cache_error_vs_time.png"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    """{method: [(seconds, rmse)]} and the table's first line (the shape)."""
    found = {}
    title = ""
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not title and line.strip():
                title = line.split(";")[0].strip()
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) >= 4 and cells[0] in ("pointwise", "sphere cache"):
                found.setdefault(cells[0], []).append((float(cells[2]), float(cells[3])))
            elif len(cells) >= 3 and cells[0].endswith("walks") and "cache points" in cells[0]:
                # zombie's rows: "seconds (+ hierarchy)", RMSE.
                found.setdefault("zombie", []).append((float(cells[1].split()[0]), float(cells[2])))
    return found, title


files, output = sys.argv[1:-1], sys.argv[-1]
figure, axes = plt.subplots(1, len(files), figsize=(5.2 * len(files), 4.2), squeeze=False)
for axis, path in zip(axes[0], files):
    found, title = rows(path)
    for method, style, label in (("pointwise", "o-", "pointwise walks"),
                                 ("sphere cache", "s-", "sphere cache"),
                                 ("zombie", "^", "zombie's boundary value caching")):
        points = sorted(found.get(method, []))
        if points:
            axis.loglog([p[0] for p in points], [p[1] for p in points], style, label=label)
    axis.set_title(title, fontsize=10)
    axis.set_xlabel("seconds (2 cores)")
    axis.set_ylabel("RMSE over the slice")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(loc="lower left", fontsize=8)
figure.tight_layout()
figure.savefig(output, dpi=110)
print("wrote", output)
