"""The readings of the accuracy study, as studies/README.md and the README quote them.

    python3 studies/accuracy/readings.py [RESULTS.csv]

From studies/accuracy/results/results.csv (by default): the runs that failed and those that drifted (errors are
read from the runs that are `ok` only), rk4's error at 10 ms, the best
error of the first-order methods, and how much closer to the reference the tuned gains bring rk4 than the
preset; then the readings of wall times (lines "timings: ..."), which differ from machine to machine and by about
20% from run to run: the Euler-type methods' cost at 10 ms, the median cost of projection over the preset gains,
and the cheapest rk45 run under 1e-7 m on the chain. scripts/check_readme_numbers.py checks that the READMEs quote
the numbers that do not depend on timings.
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

    # wall times: they differ from machine to machine and by about 20% from run to run on one
    def ms(r):
        return 1000 * float(r["seconds_per_simulated_second"])

    euler_type = [ms(r) for r in rows if r["/simulation/integrator"] in ("euler", "symplectic_euler")
                  and r["/simulation/step"] == "0.01" and r["status"] != "diverged" and not r["status"].startswith("tuning")]
    print("timings: euler-type at 10 ms: %.2g to %.2g ms per simulated second" % (min(euler_type), max(euler_type)))
    ratios = sorted(ms(run(s, i, h, "projection")) / ms(run(s, i, h, "baumgarte"))
                    for s in SCENES for i in ("euler", "symplectic_euler", "rk4", "rk45")
                    for h in ("0.01", "0.005", "0.002", "0.001", "0.0005")
                    if run(s, i, h, "projection")["status"] == "ok" and run(s, i, h, "baumgarte")["status"] == "ok")
    print("timings: projection / preset, median: %.2g" % ratios[len(ratios) // 2])
    fine = [ms(r) for r in rows if r["scene"] == "chain20" and r["/simulation/integrator"] == "rk45"
            and error(r) is not None and error(r) < 1e-7]
    print("timings: rk45 on chain20 below 1e-7 m: from %.2g ms per simulated second" % min(fine))


if __name__ == "__main__":
    main()
