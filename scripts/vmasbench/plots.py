"""The pictures: the renders of scripts/render (input | medial mesh | errors) and the scaling plot
drawn here with matplotlib (Agg)."""

import os
import sys

from .running import run
from .tables import scaling_run

RENDER = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "render")


def render(args, shape, medial, errors, png, *options):
    """Runs scripts/render SHAPE MEDIAL ERRORS PNG with its `options` (and --vmas); returns png,
    or {"error": ...} when it failed or wrote no file."""
    r = run([sys.executable, RENDER, shape, medial, errors, png, *options, "--vmas", args.vmas],
            args.timeout)
    return png if r["ok"] and os.path.exists(png) else {
        "error": r["error"] or "render wrote no file"}


SCALING_REFERENCE_SPHERES = 200  # the plot's slope-1 line goes through this series' first point


def plot_scaling(rows, model, args, png):
    """Log-log plot of the wall time against the points, one line per sphere count, and a
    dashed slope-1 line through the first point of the M = SCALING_REFERENCE_SPHERES series.
    Returns png, or {"error": ...}."""
    series = {}  # spheres: [(points, wall s, thinned)]
    for r in rows:
        if ours := scaling_run(r):
            thinned = (ours.get("thinning") or {}).get("applied")
            series.setdefault(r["spheres"], []).append((r["points"], ours["wall_s"], thinned))
    if not series:
        return {"error": "no successful run"}
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib import ticker
    except ImportError as e:
        return {"error": f"no matplotlib: {e}"}
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    for spheres, values in sorted(series.items()):
        x, y, thinned = zip(*sorted(values))
        line, = ax.plot(x, y, "o-", label=f"M = {spheres} spheres")
        hollow = [(a, b) for a, b, t in zip(x, y, thinned) if t]
        if hollow:
            ax.plot(*zip(*hollow), "o", color=line.get_color(), markerfacecolor="white")
    if any(t for values in series.values() for _, _, t in values):
        ax.plot([], [], "o", color="grey", markerfacecolor="white",
                label="hollow: run on a thinned cloud (above vmas' --max-points)")
    reference = SCALING_REFERENCE_SPHERES if SCALING_REFERENCE_SPHERES in series \
        else min(series)
    x0, y0, _ = min(series[reference])
    x1 = max(x for values in series.values() for x, _, _ in values)
    ax.plot([x0, x1], [y0, y0 * x1 / x0], "k--", linewidth=1,
            label=f"slope 1 (time ∝ points, through M = {reference})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis, label in ((ax.xaxis, count_label), (ax.yaxis, "{:g}".format)):
        axis.set_major_locator(ticker.LogLocator(subs=(1, 2, 5)))  # 1, 2, 5 × 10^k
        axis.set_major_formatter(ticker.FuncFormatter(lambda value, _, f=label: f(value)))
        axis.set_minor_formatter(ticker.NullFormatter())
    ax.set_xlabel("points in the cloud")
    ax.set_ylabel("wall time of vmas skeletonize (s)")
    ax.set_title(f"Scaling: {model}, cloud without normals "
                 f"({'threads ' + str(args.threads) if args.threads else 'all cores'})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png


def count_label(value):
    """50k, 2M, 500."""
    for scale, suffix in ((1e6, "M"), (1e3, "k")):
        if value >= scale:
            return f"{value / scale:g}{suffix}"
    return f"{value:g}"
