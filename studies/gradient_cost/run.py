#!/usr/bin/env python3
"""What one loss gradient costs against the number of parameters, as a figure (issue 6, "gradient cost").

    python3 studies/gradient_cost/run.py [--binary build/bench/tether_bench] [--min-time 0.2] [--repetitions 3]
    python3 studies/gradient_cost/run.py --json studies/gradient_cost/results.json    # redraw only

Runs the gradient benchmark (bench/gradient_bench.cc, through bench/gradient_cost.py, which also prints the
README's table), writes its JSON output to results.json and draws gradient_cost.png and .svg beside it (or in
--out): the CPU time of one gradient as a multiple of one plain simulation of the same model, against the number
of parameters P, one line per method and model. With the defaults it takes about 8 minutes on two cores.
Python 3 with matplotlib (Debian: python3-matplotlib).
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "studies"))

import bench_json  # noqa: E402
import index_page  # noqa: E402
import gradient_cost  # noqa: E402

COLORS = {"implicit": "tab:blue", "jet_factor": "tab:purple", "central": "tab:orange", "adjoint": "tab:green"}
STYLES = ["-o", "--s", ":^", "-.D"]  # one per model


def draw(report, out):
    plt = bench_json.pyplot()
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator, ScalarFormatter

    parsed = gradient_cost.parse(report)
    cells, counts, sizes = parsed["cells"], parsed["counts"], parsed["sizes"]
    figure, axes = plt.subplots(figsize=(8.5, 6.0))
    p = [counts[0], counts[-1]]
    axes.plot(p, [1 + 2 * x for x in p], color="0.6", linewidth=4, alpha=0.35,
              label="1 + 2P (central differences' plain runs)")
    for method, label in gradient_cost.METHODS:
        for n, style in zip(sizes, STYLES):
            points = [(x, cells[(n, method, x)][0]) for x in counts if (n, method, x) in cells]
            if points:
                axes.plot(*zip(*points), style, color=COLORS[method], markersize=4,
                          label=f"{label}, {gradient_cost.model_name(n)}")
    axes.set_xscale("log", base=2)
    axes.set_yscale("log")
    axes.xaxis.set_major_locator(FixedLocator(counts))
    axes.xaxis.set_major_formatter(ScalarFormatter())
    axes.xaxis.set_minor_locator(NullLocator())
    axes.yaxis.set_major_locator(FixedLocator([1, 3, 10, 30, 100, 300, 1000, 3000]))
    axes.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:g}x"))
    axes.yaxis.set_minor_locator(NullLocator())
    axes.set_xlabel("parameters P (masses and lengths or inertias, then schedule values)")
    axes.set_ylabel("one gradient / one plain simulation (CPU time)")
    durations = sorted(set(parsed["durations"].values()))
    span = ", ".join(f"{d:g}" for d in durations)
    axes.set_title(f"Cost of one loss gradient: falling chains and a 3D arm, rk4, h = 1 ms, {span} s",
                   fontsize=10)
    axes.grid(True, which="both", color="0.9")
    axes.legend(fontsize=6.5, loc="upper left", ncol=2)
    bench_json.save_figure(figure, report, out, "gradient_cost", 120)


def main(argv):
    report, out = bench_json.study_report(argv, "Runs the gradient-cost benchmark and draws it.", HERE,
                                          gradient_cost.MIN_TIME, gradient_cost.REPETITIONS, gradient_cost.run)
    print(gradient_cost.table(report))
    draw(report, out)
    print("wrote " + index_page.write_index("gradient_cost", out))


if __name__ == "__main__":
    main(sys.argv[1:])
