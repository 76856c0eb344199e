#!/usr/bin/env python3
"""Time per step against system size for each KKT solver path, as a figure (issue 6, "scaling").

    python3 studies/scaling/run.py [--binary build/bench/tether_bench] [--min-time 0.2] [--repetitions 3]
    python3 studies/scaling/run.py --json studies/scaling/results.json    # redraw only

Runs the step benchmarks of bench/chain_bench.cc (StepChain: a chain of n particles, rk4 and symplectic Euler;
StepTree: a binary tree of n particles, rk4; StepFourBar: the IFToMM A02 N-four-bar, rk4; StepHingeChain and
StepHingeTree: 3D chains and binary trees of rigid rods on hinges; each with the sparse and the dense KKT path, and
the 3D ones with the tree elimination that the auto solver takes for them), writes their JSON output to results.json and draws scaling.png and .svg beside it (or
in --out): CPU time per step against the number of constraint rows m (the size of the KKT system: n for the
chain and the tree, 6N + 2 for the four-bars), log-log, with the slope of each line fitted over m >= 100 and
reference slopes O(m) and O(m^3). It also prints the
slopes, where the dense path stops being faster (dense time / sparse time around there), and the README's
step-cost table. With the defaults it
takes about 1.5 minutes on two cores (1.3 on the machine of the README).
Python 3 with matplotlib (Debian: python3-matplotlib).
"""
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "studies"))

import bench_json  # noqa: E402
import index_page  # noqa: E402

NAME = re.compile(r"^Step(Chain|Tree|FourBar|HingeChain|HingeTree)/(rk4|symplectic_euler)_(sparse|dense|tree)/(\d+)$")
MIN_TIME, REPETITIONS = "0.2", 3
FIT_FROM = 100  # constraint rows: slopes are fitted from here on, where the per-step overhead no longer counts
MODELS = [("Chain", "chain of n particles: m = n"), ("Tree", "binary tree of n particles: m = n"),
          ("FourBar", "N-four-bar (IFToMM A02): m = 6N + 2"),
          ("HingeChain", "3D chain of n rigid rods on hinges: m = 5n"),
          ("HingeTree", "3D binary tree of n rigid rods on hinges: m = 5n")]
TABLE_SIZES = {"Chain": {10, 20, 50, 100, 200, 500, 1000, 5000}, "Tree": {10, 100, 1000, 5000},
               "FourBar": {1, 2, 10, 50, 500}, "HingeChain": {10, 100, 200, 1000}, "HingeTree": {10, 100, 1000}}
TABLE_NAMES = {"Chain": ("chain", "particles"), "Tree": ("binary tree", "particles"), "FourBar": ("four-bar", "N ="),
               "HingeChain": ("3D hinge chain", "rods"), "HingeTree": ("3D hinge tree", "rods")}
INTEGRATORS = {"rk4": "rk4", "symplectic_euler": "symplectic Euler"}
COLORS = {"sparse": "tab:blue", "dense": "tab:red", "tree": "tab:green"}
STYLES = {"rk4": "-o", "symplectic_euler": "--s"}


def parse(report):
    """{(model, integrator, path): [(rows, size, microseconds per step), ...] sorted by rows}."""
    series = {}
    for b in bench_json.measurements(report):
        match = NAME.match(b["run_name"])
        if match:
            model, integrator, path, size = match.group(1), match.group(2), match.group(3), int(match.group(4))
            point = (int(b["rows"]), size, 1e3 * bench_json.cpu_milliseconds(b))
            series.setdefault((model, integrator, path), []).append(point)
    return {key: sorted(points) for key, points in series.items()}


def slope(points):
    """Least-squares slope of log(time) against log(rows) over rows >= FIT_FROM; None with fewer than 2 points."""
    xy = [(math.log(m), math.log(t)) for m, _, t in points if m >= FIT_FROM]
    if len(xy) < 2:
        return None
    mx = sum(x for x, _ in xy) / len(xy)
    my = sum(y for _, y in xy) / len(xy)
    return sum((x - mx) * (y - my) for x, y in xy) / sum((x - mx) ** 2 for x, _ in xy)


def crossover(sparse, dense):
    """Where the dense path stops being faster, in words, with the ratio dense / sparse at the sizes around it."""
    times = {m: t for m, _, t in sparse}
    common = [(m, t / times[m]) for m, _, t in dense if m in times]  # dense time / sparse time
    if not common:
        return "no common sizes"
    wins = [i for i, (_, ratio) in enumerate(common) if ratio < 1]
    if not wins:
        return f"sparse is faster at every size (dense x{common[0][1]:.2f} at m = {common[0][0]})"
    if wins[-1] + 1 == len(common):
        return "dense is faster at every size"
    (m0, r0), (m1, r1) = common[wins[-1]], common[wins[-1] + 1]
    # the ratio interpolated log-linearly in m: where it crosses 1
    even = math.exp(math.log(m0) + math.log(r0) / (math.log(r0) - math.log(r1)) * (math.log(m1) - math.log(m0)))
    return (f"dense faster up to m = {m0} (x{r0:.2f}), sparse from m = {m1} (dense x{r1:.2f}); "
            f"break-even near m = {even:.0f}")


def microseconds(value):
    return f"{value / 1e3:.3g} ms" if value >= 1e3 else f"{value:.3g} us"


def summary(series):
    lines = []
    for model, title in MODELS:
        for integrator, name in INTEGRATORS.items():
            sparse, dense = series.get((model, integrator, "sparse")), series.get((model, integrator, "dense"))
            if not sparse and not dense:
                continue
            words = []
            tree = series.get((model, integrator, "tree"))
            for path, points in (("sparse", sparse), ("dense", dense), ("tree", tree)):
                if points:
                    s = slope(points)
                    m, _, t = points[-1]
                    words.append(f"{path} slope " + ("n/a" if s is None else f"{s:.2f}") +
                                 f" ({microseconds(t)} at m = {m})")
            if sparse and dense:
                words.append(crossover(sparse, dense))
            lines.append(f"{title.split(':')[0]}, {name}: " + "; ".join(words))
    return "\n".join(lines)


def table(series):
    """The README's step-cost table: a row per scene and size, a column per integrator and KKT path."""
    columns = [("rk4", "sparse"), ("rk4", "dense"), ("rk4", "tree"), ("symplectic_euler", "sparse"),
               ("symplectic_euler", "dense")]
    lines = ["| scene | rows | rk4, sparse | rk4, dense | rk4, tree | symplectic Euler, sparse | "
             "symplectic Euler, dense |",
             "|---|---|---|---|---|---|---|"]
    for model, _ in MODELS:
        sizes = sorted({(m, n) for (mod, _, _), points in series.items() if mod == model for m, n, _ in points
                        if n in TABLE_SIZES[model]})
        for m, n in sizes:
            cells = []
            for integrator, path in columns:
                t = [t for mm, nn, t in series.get((model, integrator, path), []) if nn == n]
                cells.append(microseconds(t[0]) if t else "")
            label, unit = TABLE_NAMES[model]
            scene = f"{label}, {unit} {n}" if unit == "N =" else f"{label}, {n} {unit}"
            lines.append(f"| {scene} | {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def draw(report, out):
    plt = bench_json.pyplot()
    series = parse(report)
    # three panels a row, so that each stays legible at the README's width (five in a row were 150 px each)
    columns = 3
    rows = (len(MODELS) + columns - 1) // columns
    figure, grid = plt.subplots(rows, columns, figsize=(15, 5.2 * rows), sharey=True, squeeze=False)
    panels = grid.ravel()
    for unused in panels[len(MODELS):]:
        unused.axis("off")
    for axes, (model, title) in zip(panels, MODELS):
        keys = [k for k in series if k[0] == model]
        for _, integrator, path in sorted(keys, key=lambda k: (list(INTEGRATORS).index(k[1]), k[2] == "dense")):
            points = series[(model, integrator, path)]
            s = slope(points)
            label = f"{INTEGRATORS[integrator]}, {path}" + (f" (slope {s:.2f})" if s is not None else "")
            axes.plot([m for m, _, _ in points], [t for _, _, t in points], STYLES[integrator],
                      color=COLORS[path], markersize=4, label=label)
        # reference slopes ending at the largest size of the path, a factor 3 above the slowest sparse line
        # and below the fastest dense line there
        for path, power, text, first in (("sparse", 1, "O(m)", 10), ("dense", 3, "O(m³)", 30)):
            ends = [series[k][-1] for k in keys if k[2] == path]
            if not ends:
                continue
            m_end = max(m for m, _, _ in ends)
            pick = max if path == "sparse" else min
            t_end = (3.0 if path == "sparse" else 1 / 3.0) * pick(t for m, _, t in ends if m == m_end)
            start = min(m for k in keys if k[2] == path for m, _, _ in series[k] if m >= first)
            xs = [start, m_end]
            axes.plot(xs, [t_end * (x / m_end) ** power for x in xs], ":", color="0.45", linewidth=1.5)
            axes.annotate(text, (start, t_end * (start / m_end) ** power), textcoords="offset points",
                          xytext=(-4, 2), ha="right", fontsize=11, color="0.3")
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_title(title, fontsize=12)
        axes.set_xlabel("constraint rows m (size of the KKT system)", fontsize=11)
        axes.tick_params(labelsize=10)
        axes.grid(True, which="major", color="0.85")
        axes.grid(True, which="minor", color="0.95")
        axes.legend(fontsize=10, loc="upper left")
    for row in grid:
        row[0].set_ylabel("CPU time per step (µs)", fontsize=11)
    figure.suptitle(f"Time per step against size for each KKT path (h = 1 ms; slopes fitted over m ≥ {FIT_FROM})",
                    fontsize=13)
    bench_json.save_figure(figure, report, out, "scaling", 110)


def main(argv):
    def run_steps(binary, min_time, repetitions, extra):
        return bench_json.run(binary, "^Step(Chain|Tree|FourBar|HingeChain|HingeTree)/", min_time, repetitions, extra)

    report, out = bench_json.study_report(argv, "Runs the step benchmarks and draws time per step against size.",
                                          HERE, MIN_TIME, REPETITIONS, run_steps)
    print(summary(parse(report)))
    print()
    print(table(parse(report)))
    print("host: " + bench_json.host(report))
    draw(report, out)
    print("wrote " + index_page.write_index("scaling", out))


if __name__ == "__main__":
    main(sys.argv[1:])
