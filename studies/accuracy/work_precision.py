#!/usr/bin/env python3
"""Work-precision diagrams of tether, MuJoCo and Simbody: the error at the end against the time per simulated
second, log-log, per scene, from the peer benchmark's report (bench/peer/results_simbody.json, written by
bench/peer/simbody_side_by_side.py; bench/peer/README.md has the scenes and the settings). Draws
studies/accuracy/results/work_precision.png (and .svg) and prints, per scene, the cheapest engine at each
accuracy: the fastest run whose error is within 1e-3, 1e-6 and 1e-9 m.

    python3 studies/accuracy/work_precision.py [--json bench/peer/results_simbody.json]

Curves: tether's rk45 with projection at tolerances 1e-4 to 1e-12 and its rk4 (Baumgarte (100, 2500)) at
h = 2, 1, 0.5 and 0.25 ms; MuJoCo's RK4 at the same steps (its soft equality constraints on the loops); Simbody's
Runge-Kutta-Merson at accuracies 1e-4 to 1e-12 and CPodes at 1e-6 and 1e-8. The reference is the N-four-bar's
exact motion and, elsewhere, Simbody's Runge-Kutta-Merson at 1e-12 (so that run is not drawn). Errors below
1e-13 m are drawn at 1e-13 (rounding). Standard library and matplotlib.
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "bench", "peer"))
import bench_json  # noqa: E402
import simbody_side_by_side as peers  # noqa: E402

FLOOR = 1e-13  # m
BANDS = (1e-3, 1e-6, 1e-9)
CURVES = [  # (engine, method prefix, label, style)
    ("tether", "rk45", "tether rk45 + projection (tolerance)", dict(color="C0", marker="o")),
    ("tether", "rk4", "tether rk4, Baumgarte (step)", dict(color="C0", marker="s", linestyle="--")),
    ("mujoco", "rk4", "MuJoCo RK4 (step)", dict(color="C3", marker="^", linestyle="--")),
    ("simbody", "rkm", "Simbody Runge-Kutta-Merson (accuracy)", dict(color="C2", marker="D")),
    ("simbody", "cpodes", "Simbody CPodes (accuracy)", dict(color="C2", marker="x", linestyle=":")),
]


def points(table, scene, engine, prefix):
    """(seconds per simulated second, error) of the runs of one curve, in the order of their cost."""
    out = []
    for s, e, method, entry in table:
        if s != scene or e != engine or method.split("_")[0] != prefix or entry.get("error_occurred"):
            continue
        if f"{e}/{method}" == peers.REFERENCE and not scene.startswith("four_bar"):
            continue
        out.append((peers.per_simulated_second(entry) / 1e3, max(entry["error_m"], FLOOR), method))
    return sorted(out)


def cheapest(table, scene):
    """Per accuracy band, (engine, method, seconds per simulated second) of the fastest run within it."""
    out = {}
    for band in BANDS:
        best = None
        for engine, prefix, _, _ in CURVES:
            for seconds, error, method in points(table, scene, engine, prefix):
                if error <= band and (best is None or seconds < best[2]):
                    best = (engine, method, seconds)
        out[band] = best
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", default=os.path.join(ROOT, "bench", "peer", "results_simbody.json"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    args = ap.parse_args()
    report = bench_json.load(args.json)
    table = peers.runs(report)
    plt = bench_json.pyplot()
    scenes = list(peers.SCENES)
    figure, axes = plt.subplots(2, 4, figsize=(17, 8))
    for ax, scene in zip(axes.flat, scenes):
        for engine, prefix, label, style in CURVES:
            curve = points(table, scene, engine, prefix)
            if curve:
                ax.loglog([p[0] for p in curve], [p[1] for p in curve], label=label, markersize=5, **style)
        ax.set_title(peers.SCENES[scene], fontsize=10)
        ax.set_xlabel("time per simulated second (s, one core)")
        ax.set_ylabel("error of the centres at the end (m)")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes.flat[len(scenes):]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    axes.flat[len(scenes)].legend(handles, labels, loc="center", fontsize=9)
    os.makedirs(args.out, exist_ok=True)
    bench_json.save_figure(figure, report, args.out, "work_precision", 110)
    for scene in scenes:
        parts = []
        for band, best in cheapest(table, scene).items():
            if best is None:
                parts.append(f"within {band:g} m: none")
            else:
                engine, method, seconds = best
                parts.append(f"within {band:g} m: {peers.ENGINES[engine]} ({peers.method_label(engine, method)}, "
                             f"{peers.duration(seconds * 1e3)})")
        print(f"{peers.SCENES[scene]}: " + "; ".join(parts))
    print("host: " + bench_json.host(report))


if __name__ == "__main__":
    main()
