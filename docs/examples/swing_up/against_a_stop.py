#!/usr/bin/env python3
"""Swings the weak pendulum up in 2.5 s by bouncing it off a joint stop, where no swing without the stop gets there.

    python3 docs/examples/swing_up/against_a_stop.py [--tether build/tether] [--out DIR]

docs/examples/swing_up/against_a_stop.json is the README's pendulum (1 m, 1 kg rod on an axle, a motor of at most
2 N m, which cannot hold it level: gravity's torque there is 4.9 N m) with an elastic stop (e = 1) at -0.35 rad
and 11 knots over 2.5 s. The task: from hanging at rest to within [3, 3.3] rad at 2.5 s, turning at most
0.2 rad/s, least effort. The fit (2 starts, 6 shooting segments) crosses the impacts in its gradients; the same
fit on the scene without the stop (its "range" and "restitution" removed), given 8 starts, meets no constraint
set: the stop reverses the swing at no cost in energy, which the motor would otherwise spend time doing.

Prints the fit with the stop, the impacts of one run of the written scene (`tether simulate --events`) and its
state at 2.5 s, then the outcome without the stop. Writes DIR/swung.json (default: a temporary folder). Exit
status 1 unless the fit with the stop succeeds, its scene bounces off the stop and ends within the constraints,
and the fit without the stop fails.
"""
import argparse
import csv
import io
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
KNOTS = "/effects/1/schedule/values/*"
FLAGS = ["--param", KNOTS, "--bound", KNOTS + "=-2:2", "--effort", "0.1",
         "--at-least", "axle.angle=3@2.5", "--at-most", "axle.angle=3.3@2.5",
         "--at-least", "axle.omega=-0.2@2.5", "--at-most", "axle.omega=0.2@2.5", "--segments", "6"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    out = args.out or tempfile.mkdtemp(prefix="tether_stop_swing_")
    scene = os.path.join(ROOT, "docs", "examples", "swing_up", "against_a_stop.json")
    swung = os.path.join(out, "swung.json")

    fit = subprocess.run([args.tether, "fit", scene, *FLAGS, "--starts", "2", "-o", swung],
                         capture_output=True, text=True)
    if fit.returncode != 0:
        print(fit.stderr, file=sys.stderr)
        return 1
    report = json.loads(fit.stdout)
    print("with the stop: %d of %d starts met the constraints, cost %.4f" %
          (report["starts"]["feasible"], report["starts"]["count"], report["final_cost"]))
    events = os.path.join(out, "events.csv")
    run = subprocess.run([args.tether, "simulate", swung, "--events", events], capture_output=True, text=True,
                         check=True)
    last = list(csv.DictReader(io.StringIO(run.stdout)))[-1]
    with open(events) as f:
        impacts = [row for row in csv.DictReader(f) if row["kind"] == "impact"]
    for row in impacts:
        print("  impact at t = %.4f s, %.3f rad/s in, %.3f rad/s out" %
              (float(row["t"]), float(row["speed_before"]), float(row["speed_after"])))
    angle, omega = float(last["axle.angle"]), float(last["axle.omega"])
    print("  written scene at t = %s s: angle %.4f rad, omega %.4f rad/s" % (last["t"], angle, omega))

    without = json.load(open(scene))
    for key in ("range", "restitution"):
        del without["constraints"][0][key]
    free = os.path.join(out, "without_stop.json")
    with open(free, "w") as f:
        json.dump(without, f)
    unstopped = subprocess.run([args.tether, "fit", free, *FLAGS, "--starts", "8"], capture_output=True, text=True)
    other = json.loads(unstopped.stdout)
    print("without the stop: exit status %d, %d of %d starts met the constraints" %
          (unstopped.returncode, other["starts"]["feasible"], other["starts"]["count"]))
    met = 3.0 - 1e-6 <= angle <= 3.3 + 1e-6 and abs(omega) <= 0.2 + 1e-6
    return 0 if impacts and met and unstopped.returncode == 1 else 1


if __name__ == "__main__":
    sys.exit(main())
