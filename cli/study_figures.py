"""The figures of a tether study; `tether study` embeds this script and runs it with Debian's python3-matplotlib.

    python3 study_figures.py RESULTS.csv FOLDER N_COLUMNS FIGURES [MARKS.json]

RESULTS.csv has N_COLUMNS swept columns, then the metrics, then `status`. FIGURES is the study's validated
`figures` list as JSON text; MARKS.json holds what gain_map figures mark (studies/gain_map.h).
Figure types (PNG and SVG each, in FOLDER):
  lines     METRIC.png per metric: the metric against the first swept column, a line per combination of the
            other columns that take several values;
  pareto    pareto_Y_vs_X.png: every run as a point, a panel per scene, colour by stabilization (or the first
            other varying column), marker by integrator; the Pareto front (no run is better in both) is drawn
            and written to pareto_Y_vs_X.csv;
  gain_map  gain_map_METRIC.png: the metric over the swept (alpha, beta) grid, a panel per combination of the
            other columns, diverged runs hatched, drifted runs marked, with the stability bound and the marks.
Diverged runs and, on log axes, values that are not positive are left out.
"""
import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = "os^Dv<>ph*"
# Colour-blind-safe tab10 colours, then the same colours dashed, dotted and dash-dotted: 40 lines stay apart
COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf"]
LINE_STYLES = ["-", "--", ":", "-."]

# Axis labels with units, for the metrics and the pointers studies sweep most
LABELS = {
    "max_constraint_error": "largest constraint violation (m)",
    "rms_position_error": "RMS position error against the reference (m)",
    "energy_drift": "energy drift, max |E - E0| / max(|E0|, 1 J)",
    "seconds": "wall time (s)",
    "seconds_per_simulated_second": "wall time per simulated second (s/s)",
    "alpha": "Baumgarte alpha (1/s)",
    "beta": "Baumgarte beta (1/s^2)",
    "/simulation/step": "step h (s)",
    "/simulation/duration": "duration (s)",
    "/simulation/tolerance": "rk45 tolerance",
    "/stabilization/alpha": "alpha (1/s)",
    "/stabilization/beta": "beta (1/s^2)",
}


def label(name):
    return LABELS.get(name, name)


def line_style(k):
    """Colour, line style and marker of the k-th line."""
    return COLOURS[k % len(COLOURS)], LINE_STYLES[(k // len(COLOURS)) % len(LINE_STYLES)], MARKERS[k % len(MARKERS)]


def number(text):
    try:
        value = float(text)
        return None if math.isnan(value) else value
    except ValueError:
        return None


def short(column):
    return column.rsplit("/", 1)[-1]


def setting(column, value):
    """ "name=value unit" for legends and titles, the unit as LABELS gives it (its last parentheses)."""
    unit = re.search(r"\(([^()]*)\)$", LABELS.get(column, ""))
    return "%s=%s%s" % (short(column), value, " " + unit.group(1) if unit else "")


def spans_decades(values):
    positive = [v for v in values if v is not None and v > 0]
    return len(positive) > 1 and max(positive) / min(positive) > 100


def save(fig, folder, name):
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(folder, "%s.%s" % (name, ext)), dpi=110)
    plt.close(fig)


class Results:
    def __init__(self, path, n):
        with open(path) as f:
            reader = csv.reader(f)
            header = next(reader)
            self.rows = list(reader)
        self.columns, self.metrics = header[:n], header[n:-1]
        self.n = n

    def metric(self, row, name):
        return number(row[self.n + self.metrics.index(name)])

    def varying(self, exclude=()):
        return [k for k, c in enumerate(self.columns)
                if c not in exclude and len({r[k] for r in self.rows}) > 1]


def lines(results, folder):
    rows = results.rows
    varying = [k for k in results.varying() if k > 0]
    x_numeric = all(number(r[0]) is not None for r in rows)
    for metric in results.metrics:
        log = spans_decades([results.metric(r, metric) for r in rows])
        fig, ax = plt.subplots(figsize=(8.0, 4.4))
        groups = {}
        for r in rows:
            groups.setdefault(tuple(r[k] for k in varying), []).append(r)
        for index, (key, members) in enumerate(groups.items()):
            pts = [(number(r[0]) if x_numeric else r[0], results.metric(r, metric)) for r in members]
            pts = [(x, y) for x, y in pts if y is not None and (y > 0 or not log)]
            name = ", ".join(setting(results.columns[k], v) for k, v in zip(varying, key)) or metric
            colour, style, marker = line_style(index)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour, ls=style, marker=marker, ms=4, label=name)
        if log:
            ax.set_yscale("log")
        if x_numeric and all(number(r[0]) > 0 for r in rows):
            ax.set_xscale("log")
        ax.set_xlabel(label(results.columns[0]))
        ax.set_ylabel(label(metric))
        ax.grid(alpha=0.3, which="both")
        if len(groups) > 1:
            ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
        save(fig, folder, metric)


def pareto_front(points):
    """The points no other point beats in both coordinates (smaller is better), sorted by x."""
    front = []
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    return front


def pareto(results, folder, x_name, y_name):
    cols = results.columns
    scene = cols.index("scene") if "scene" in cols else None
    others = results.varying(exclude=("scene",))
    colour_col = others[0] if others else None
    if "/stabilization/method" in cols:
        colour_col = cols.index("/stabilization/method")
    marker_col = cols.index("/simulation/integrator") if "/simulation/integrator" in cols else None
    if marker_col == colour_col:
        marker_col = None
    panels = list(dict.fromkeys(r[scene] for r in results.rows)) if scene is not None else [None]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels) + 1.8, 4.4), squeeze=False)
    colour_values = list(dict.fromkeys(r[colour_col] for r in results.rows)) if colour_col is not None else [None]
    marker_values = list(dict.fromkeys(r[marker_col] for r in results.rows)) if marker_col is not None else [None]
    palette = COLOURS
    front_rows = []
    for ax, panel in zip(axes[0], panels):
        points = []
        for r in results.rows:
            if panel is not None and r[scene] != panel:
                continue
            x, y = results.metric(r, x_name), results.metric(r, y_name)
            if x is None or y is None or x <= 0 or y <= 0:
                continue
            c = colour_values.index(r[colour_col]) if colour_col is not None else 0
            m = marker_values.index(r[marker_col]) if marker_col is not None else 0
            ax.scatter([x], [y], color=palette[c % len(palette)], marker=MARKERS[m % len(MARKERS)], s=28, alpha=0.85)
            points.append((x, y, r))
        front = pareto_front(points)
        ax.step([p[0] for p in front], [p[1] for p in front], where="post", color="black", lw=1.0, zorder=0)
        ax.scatter([p[0] for p in front], [p[1] for p in front], facecolors="none", edgecolors="black", s=80, lw=1.0)
        front_rows += [p[2] for p in front]
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label(x_name))
        ax.set_ylabel(label(y_name))
        ax.set_title(panel if panel is not None else "", fontsize=10)
        ax.grid(alpha=0.3, which="both")
    handles = [plt.Line2D([], [], color=palette[i % len(palette)], marker="o", ls="", label=str(v))
               for i, v in enumerate(colour_values) if v is not None]
    handles += [plt.Line2D([], [], color="grey", marker=MARKERS[i % len(MARKERS)], ls="", label=str(v))
                for i, v in enumerate(marker_values) if v is not None]
    handles.append(plt.Line2D([], [], color="black", marker="o", mfc="none", label="Pareto front"))
    axes[0][-1].legend(handles=handles, fontsize=7, loc="center left", bbox_to_anchor=(1.02, 0.5))
    name = "pareto_%s_vs_%s" % (y_name, x_name)
    save(fig, folder, name)
    with open(os.path.join(folder, name + ".csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(cols + results.metrics)
        for r in front_rows:
            writer.writerow(r[:-1])


def edges(values):
    """Cell edges around sorted positive grid values: geometric midpoints, extended by half a step."""
    if len(values) == 1:
        return [values[0] / 1.5, values[0] * 1.5]
    mids = [math.sqrt(a * b) for a, b in zip(values, values[1:])]
    return [values[0] ** 2 / mids[0]] + mids + [values[-1] ** 2 / mids[-1]]


def gain_map(results, folder, metric, marks):
    cols = results.columns
    ia, ib = cols.index("/stabilization/alpha"), cols.index("/stabilization/beta")
    alphas = sorted({number(r[ia]) for r in results.rows})
    betas = sorted({number(r[ib]) for r in results.rows})
    panels = marks["panels"]
    ncols = min(2, len(panels))
    nrows = (len(panels) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(5.6 * ncols + 1.2, 4.6 * nrows + 0.5), squeeze=False)
    fig.subplots_adjust(bottom=0.1 + 0.05 / nrows, hspace=0.3)
    values = [v for v in (results.metric(r, metric) for r in results.rows) if v is not None and v > 0]
    norm = colors.LogNorm(vmin=min(values), vmax=max(values)) if values else None
    mesh = None
    for index, panel in enumerate(panels):
        ax = axes[index // ncols][index % ncols]
        grid = [[float("nan")] * len(alphas) for _ in betas]
        diverged, drifted = [], []
        for r in results.rows:
            if any(r[cols.index(c)] != cell for c, cell in panel["values"].items()):
                continue
            a, b = alphas.index(number(r[ia])), betas.index(number(r[ib]))
            value = results.metric(r, metric)
            if value is None:
                diverged.append((number(r[ia]), number(r[ib])))
            elif value > 0:
                grid[b][a] = value
            if r[-1].startswith("drifted"):
                drifted.append((number(r[ia]), number(r[ib])))
        mesh = ax.pcolormesh(edges(alphas), edges(betas), grid, norm=norm, cmap="viridis", shading="flat")
        blown = [[1.0 if (a, b) in diverged else float("nan") for a in alphas] for b in betas]
        ax.pcolormesh(edges(alphas), edges(betas), blown, cmap=colors.ListedColormap(["0.88"]), shading="flat")
        if diverged:
            ax.scatter([d[0] for d in diverged], [d[1] for d in diverged], marker="x", color="0.45", s=22,
                       zorder=4, label="diverged")
        if drifted:
            ax.scatter([d[0] for d in drifted], [d[1] for d in drifted], marker="+", color="black", s=30,
                       zorder=4, label="drifted past 1% of the length scale")
        bound = panel["bound"]
        ax.plot([p[0] for p in bound], [p[1] for p in bound], color="red", lw=1.3, zorder=3,
                label="stability bound")
        for k, mark in enumerate(panel["marks"]):
            ax.scatter([mark["alpha"]], [mark["beta"]], marker=MARKERS[(k + 2) % len(MARKERS)], color="white",
                       edgecolors="black", s=70, zorder=5, label=mark["name"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        e_a, e_b = edges(alphas), edges(betas)
        ax.set_xlim(e_a[0], e_a[-1])
        ax.set_ylim(e_b[0], e_b[-1])
        ax.set_xlabel("alpha (1/s)")
        ax.set_ylabel("beta (1/s^2)")
        varying = [cols[k] for k in results.varying()]
        ax.set_title(", ".join(setting(c, v) for c, v in panel["values"].items() if c in varying), fontsize=10)
    legend = {}  # every panel's entries, once each (only some panels have drifted runs)
    for ax in axes.ravel():
        for handle, text in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(text, handle)
    fig.legend(list(legend.values()), list(legend.keys()), fontsize=8, loc="lower center", ncol=4)
    for index in range(len(panels), nrows * ncols):
        axes[index // ncols][index % ncols].axis("off")
    if mesh is not None:
        fig.colorbar(mesh, ax=axes.ravel().tolist(), label=label(metric), shrink=0.9)
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(folder, "gain_map_%s.%s" % (metric, ext)), dpi=110)
    plt.close(fig)


def main():
    path, folder, n, figures = sys.argv[1], sys.argv[2], int(sys.argv[3]), json.loads(sys.argv[4])
    marks = {}
    if len(sys.argv) > 5:
        with open(sys.argv[5]) as f:
            marks = json.load(f)
    results = Results(path, n)
    for figure in figures:
        if figure["type"] == "lines":
            lines(results, folder)
        elif figure["type"] == "pareto":
            pareto(results, folder, figure["x"], figure["y"])
        elif figure["type"] == "gain_map":
            gain_map(results, folder, figure["color"], marks)


main()
