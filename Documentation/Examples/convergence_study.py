"""Convergence of the walk-on-spheres value, gradient and Hessian estimators
with and without control variates, after Fig. 15 of Sawhney & Crane, "Monte
Carlo Geometry Processing" (2020).

Runs GridFreeConvergenceStudy (a 2D Poisson problem on a non-convex flower,
errors against the closed-form solution on a regular grid of points) or reads
a CSV it wrote, then plots the L2 (root mean square over the points) and L-inf
(maximum) errors against walks per point on log-log axes, with a reference
slope of -1/2, and prints the fitted slopes and the error ratios without/with
control variates at 1024 walks.

    /usr/bin/python3 Documentation/Examples/convergence_study.py
    /usr/bin/python3 Documentation/Examples/convergence_study.py --csv-in convergence.csv

Exits 1 when the CSV is malformed, a fitted slope is not finite or matplotlib
is missing (Debian: python3-matplotlib, which ./gridfree installs).
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
QUANTITIES = ("value", "gradient", "hessian")
LABELS = {"value": "value", "gradient": "gradient", "hessian": "Hessian"}
COLUMNS = ["walks", "control_variates", "quantity", "l2_error", "linf_error", "mean_stderr"]
RATIO_WALKS = 1024


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "GridFreeConvergenceStudy"),
                        help="the study executable (default: build/bin/GridFreeConvergenceStudy)")
    parser.add_argument("--csv-in", help="read this CSV instead of running the executable")
    parser.add_argument("--csv", default=os.path.join(ROOT, "Documentation", "Images", "convergence.csv"),
                        help="where the executable writes its CSV")
    parser.add_argument("--png", default=os.path.join(ROOT, "Documentation", "Images", "convergence.png"),
                        help="the plot")
    parser.add_argument("--max-walks", type=int, default=16384)
    parser.add_argument("--points", type=int, default=400)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=2)
    return parser.parse_args()


def fail(message):
    print("convergence_study: " + message, file=sys.stderr)
    sys.exit(1)


def run_study(args):
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    command = [args.exe, "--max-walks", str(args.max_walks), "--points", str(args.points),
               "--seed", str(args.seed), "--threads", str(args.threads), "--csv", args.csv]
    print("running " + " ".join(command), flush=True)
    try:
        result = subprocess.run(command)
    except OSError as error:
        fail("cannot run %s: %s (build the GridFreeConvergenceStudy target)" % (args.exe, error))
    if result.returncode != 0:
        fail("%s exited with %d" % (args.exe, result.returncode))
    return args.csv


def read_table(path):
    """{(cv, quantity): {"walks", "l2", "linf", "stderr"} arrays sorted by walks}."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as error:
        fail("cannot read %s: %s" % (path, error))
    if not rows or rows[0] != COLUMNS:
        fail("%s: header is not %s" % (path, ",".join(COLUMNS)))
    data = {}
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(COLUMNS):
            fail("%s:%d: expected %d fields, got %d" % (path, number, len(COLUMNS), len(row)))
        try:
            walks, cv = int(row[0]), int(row[1])
            numbers = [float(x) for x in row[3:]]
        except ValueError:
            fail("%s:%d: not a number in %s" % (path, number, ",".join(row)))
        quantity = row[2]
        if quantity not in QUANTITIES or cv not in (0, 1) or walks < 1:
            fail("%s:%d: unexpected row %s" % (path, number, ",".join(row)))
        if not all(math.isfinite(x) and x > 0 for x in numbers):
            fail("%s:%d: errors must be finite and positive: %s" % (path, number, ",".join(row)))
        data.setdefault((cv, quantity), []).append([walks] + numbers)
    if len(data) != 2 * len(QUANTITIES):
        fail("%s: expected rows for every quantity with and without control variates" % path)
    table = {}
    walk_sets = set()
    for key, entries in data.items():
        entries.sort()
        a = np.array(entries, dtype=float)
        if len(set(a[:, 0])) != len(a):
            fail("%s: repeated walk counts for %s" % (path, key))
        walk_sets.add(tuple(a[:, 0]))
        table[key] = {"walks": a[:, 0], "l2": a[:, 1], "linf": a[:, 2], "stderr": a[:, 3]}
    if len(walk_sets) != 1 or len(next(iter(walk_sets))) < 2:
        fail("%s: every series needs the same walk counts, at least two of them" % path)
    return table


def slope(walks, error):
    return float(np.polyfit(np.log(walks), np.log(error), 1)[0])


def summarize(table):
    """Prints slopes and ratios; returns False when a slope is not finite."""
    finite = True
    print("\nfitted log-log slopes of the error against walks (expected -0.5):")
    print("  %-9s %-4s %8s %8s" % ("quantity", "CV", "L2", "Linf"))
    for cv in (1, 0):
        for q in QUANTITIES:
            s = table[(cv, q)]
            l2, linf = slope(s["walks"], s["l2"]), slope(s["walks"], s["linf"])
            finite = finite and math.isfinite(l2) and math.isfinite(linf)
            print("  %-9s %-4s %+8.3f %+8.3f" % (LABELS[q], "on" if cv else "off", l2, linf))
    walks = table[(1, "value")]["walks"]
    k = int(np.nonzero(walks == RATIO_WALKS)[0][0]) if RATIO_WALKS in walks else len(walks) - 1
    print("\nat %d walks: L2 error without / with control variates" % walks[k])
    print("  %-9s %11s %11s %7s" % ("quantity", "without CV", "with CV", "ratio"))
    for q in QUANTITIES:
        off, on = table[(0, q)]["l2"][k], table[(1, q)]["l2"][k]
        print("  %-9s %11.4e %11.4e %6.2fx" % (LABELS[q], off, on, off / on))
    return finite


def plot(table, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
    except ImportError:
        print("convergence_study: matplotlib is missing (python3-matplotlib)", file=sys.stderr)
        sys.exit(1)
    colors = {"value": "tab:blue", "gradient": "tab:orange", "hessian": "tab:green"}
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2), sharex=True)
    for ax, norm, title in ((axes[0], "l2", "L2 error (RMS over points)"),
                            (axes[1], "linf", "L\u221e error (max over points)")):
        for q in QUANTITIES:
            for cv, style, marker in ((0, "--", "o"), (1, "-", "s")):
                s = table[(cv, q)]
                ax.loglog(s["walks"], s[norm], style, marker=marker, markersize=3.5,
                          color=colors[q], label="%s, %s" % (LABELS[q], "with CV" if cv else "no CV"))
        # Reference slope -1/2 through the geometric middle of all the curves.
        walks = table[(1, "value")]["walks"]
        level = np.exp(np.mean([np.log(table[key][norm]).mean() for key in table]))
        middle = np.exp(np.log(walks).mean())
        ax.loglog(walks, level * (walks / middle) ** -0.5, ":", color="black", linewidth=1.5,
                  label="slope \u22121/2")
        ax.set_title(title)
        ax.set_xlabel("walks per point")
        ax.set_xscale("log", base=2)
        ticks = walks if len(walks) <= 8 else walks[::2]
        ax.set_xticks(ticks)
        ax.set_xticklabels(["%d" % w for w in ticks])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("error")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8.5, frameon=False)
    fig.suptitle("Walk on spheres on a 2D Poisson problem: convergence with (solid) and without "
                 "(dashed) control variates (cf. Sawhney & Crane 2020, Fig. 15)", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print("\nwrote %s" % path)


def main():
    args = parse_arguments()
    path = args.csv_in if args.csv_in else run_study(args)
    table = read_table(path)
    if not summarize(table):
        fail("a fitted slope is not finite")
    plot(table, args.png)
    if not args.csv_in:
        print("wrote %s" % args.csv)


if __name__ == "__main__":
    main()
