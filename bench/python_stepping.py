#!/usr/bin/env python3
"""The cost of stepping a run from Python (Scene.stepper, docs/stepping.md) beyond the steps themselves.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_stepping.py [--repeats 7]

In one process: on scenes/pendulum.json (10000 rk4 steps of 1 ms), the time of simulate() (every step taken and
recorded in C++) against the same run stepped from Python in blocks of 100 steps and of 1; on
scenes/cart_pole.json, simulate() against a control loop that reads a column, sets the rail's force and takes a
step. Prints the medians of the repeats, per step, and the overhead per step over simulate's.
"""
import argparse
import os
import statistics
import time

import tether

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def timed(run, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    print("medians of %d runs, per step:" % args.repeats)
    scene = tether.Scene.load(os.path.join(ROOT, "scenes", "pendulum.json"))
    steps = 10000
    simulate = timed(lambda: scene.simulate(), args.repeats)
    print("scenes/pendulum.json, %d rk4 steps of 1 ms" % steps)
    print("  simulate():                     %6.3f us" % (simulate / steps * 1e6))
    for size in (100, 1):
        def run():
            sim = scene.stepper()
            for _ in range(steps // size):
                sim.step(size)
        t = timed(run, args.repeats)
        print("  stepper, blocks of %3d steps:   %6.3f us, %6.3f us beyond simulate's" %
              (size, t / steps * 1e6, (t - simulate) / steps * 1e6))
    cart_pole = tether.Scene.load(os.path.join(ROOT, "scenes", "cart_pole.json"))
    steps = 300
    simulate = timed(lambda: cart_pole.simulate(), args.repeats * 10)

    def control_loop():
        sim = cart_pole.stepper()
        for _ in range(steps):
            sim.set_control("rail", -0.1 * sim["pivot.angle"])
            sim.step()
    t = timed(control_loop, args.repeats * 10)
    print("scenes/cart_pole.json, %d rk4 steps of 10 ms" % steps)
    print("  simulate():                     %6.3f us" % (simulate / steps * 1e6))
    print("  a control loop (a column read, set_control, step()): %6.3f us, %6.3f us beyond simulate's" %
          (t / steps * 1e6, (t - simulate) / steps * 1e6))


if __name__ == "__main__":
    main()
