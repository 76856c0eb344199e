"""The readings of the accuracy study that do not depend on timings, as studies/README.md and the README quote them.

    python3 studies/accuracy/readings.py [RESULTS.csv]

From studies/accuracy/results/results.csv (by default): the runs that failed and those that drifted (errors are
read from the runs that are `ok` only), rk4's error at 10 ms, the best
error of the first-order methods, and how much closer to the reference the tuned gains bring rk4 than the
preset. (The Pareto fronts depend on wall times and are left to the figures.) scripts/check_readme_numbers.py
checks that the READMEs quote these numbers.
"""
import csv
import os
import sys
from collections import Counter

SCENES = ("double_pendulum", "four_bar", "chain20")


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results", "results.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))

    def run(scene, integrator, step, method):
        for r in rows:
            if (r["scene"], r["/simulation/integrator"], r["/simulation/step"], r["/stabilization/method"]) == \
                    (scene, integrator, step, method):
                return r
        raise KeyError((scene, integrator, step, method))

    def error(r):
        return float(r["rms_position_error"]) if r["status"] == "ok" else None

    def count(label, selected):
        by_scene = Counter(r["scene"] for r in selected)
        print("%s: %d (%s)" % (label, len(selected), ", ".join("%s %d" % (s, by_scene[s]) for s in SCENES if by_scene[s])))

    # a drifted run was measured, but its constraints ended more than 1% of the length scale off
    count("failed runs", [r for r in rows if r["status"] != "ok" and not r["status"].startswith("drifted")])
    count("drifted runs", [r for r in rows if r["status"].startswith("drifted")])
    print("rk4 with tuned gains at 10 ms: " + ", ".join(
        "%.1e m (%s)" % (error(run(s, "rk4", "0.01", "tuned")), s) for s in SCENES))
    best = []
    for s in SCENES:
        errors = [error(r) for r in rows if r["scene"] == s and r["/simulation/integrator"] in ("euler", "symplectic_euler")]
        best.append("%.1e m (%s)" % (min(e for e in errors if e is not None), s))
    print("first-order methods at best: " + ", ".join(best))
    factors = []
    for s, step in (("double_pendulum", "0.01"), ("four_bar", "0.01"), ("chain20", "0.005")):
        preset, tuned = error(run(s, "rk4", step, "baumgarte")), error(run(s, "rk4", step, "tuned"))
        factors.append("%.2g (%s, %g ms)" % (preset / tuned, s, 1000 * float(step)))
    print("rk4, preset error / tuned error: " + ", ".join(factors))


if __name__ == "__main__":
    main()
