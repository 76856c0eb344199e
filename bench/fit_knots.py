#!/usr/bin/env python3
"""Times `tether fit` of a 200-knot force schedule with Jets and with the adjoint (issue 17), and prints both.

    python3 bench/fit_knots.py [--tether build/tether] [--runs 3] [--knots 200]

The problem: a planar chain of 10 particles (0.1 kg on 0.1 m links) hanging from the origin at rest, pushed at
its free end by a force schedule of KNOTS values of the x component over 1 s (rk4, h = 1 ms, Baumgarte
alpha = 20, beta = 100). The targets are the free end's x and y at 20 times of the run of the true schedule (a
sine of 1 N); the fit starts from the zero schedule, with --smooth 1e-4 (the 40 target cells cannot fix 200
values alone). Both runs use nlopt:LD_LBFGS with the command's default budget and stop where it converges,
after the same steps (their gradients agree to 1e-8): `--method jet` forms each gradient from ceil(KNOTS / 4)
Jet runs, `--method adjoint` by one adjoint run. Both then take the Jacobian by Jets for the report's
identifiability and uncertainty. Prints the median wall time of RUNS fits each, their final costs and the
ratio; about 2 minutes with the defaults. Standard library only.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

LINKS, LINK, MASS, DURATION = 10, 0.1, 0.1, 1.0


def scene(values, knots):
    times = [DURATION * j / (knots - 1) for j in range(knots)]
    bodies = [{"name": f"p{k}", "type": "particle", "mass": MASS, "position": [0.0, -LINK * (k + 1)]}
              for k in range(LINKS)]
    constraints = [{"type": "distance", "bodies": ["world" if k == 0 else f"p{k - 1}", f"p{k}"], "length": LINK}
                   for k in range(LINKS)]
    effects = [{"type": "gravity", "acceleration": [0.0, -9.81]},
               {"type": "force", "body": f"p{LINKS - 1}",
                "schedule": {"times": times, "values": [[v, 0.0] for v in values]}}]
    return {"dimension": 2, "bodies": bodies, "constraints": constraints, "effects": effects,
            "simulation": {"integrator": "rk4", "step": 1e-3, "duration": DURATION},
            "stabilization": {"method": "baumgarte", "alpha": 20.0, "beta": 100.0}}


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tether", default="build/tether")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--knots", type=int, default=200)
    args = parser.parse_args(argv)
    work = tempfile.mkdtemp(prefix="tether-fit-knots-")
    knots = args.knots
    truth = [math.sin(2 * math.pi * j / (knots - 1)) for j in range(knots)]
    with open(os.path.join(work, "truth.json"), "w") as f:
        json.dump(scene(truth, knots), f)
    with open(os.path.join(work, "guess.json"), "w") as f:
        json.dump(scene([0.0] * knots, knots), f)
    run = subprocess.run([args.tether, "simulate", os.path.join(work, "truth.json"), "--every", "50"],
                         capture_output=True, text=True, check=True).stdout.splitlines()
    header = run[0].split(",")
    end = f"p{LINKS - 1}"
    columns = [header.index("t"), header.index(end + ".x"), header.index(end + ".y")]
    with open(os.path.join(work, "targets.csv"), "w") as f:
        f.write(f"t,{end}.x,{end}.y\n")
        for line in run[2:]:  # every 50 ms after t = 0
            cells = line.split(",")
            f.write(",".join(cells[c] for c in columns) + "\n")
    command = [args.tether, "fit", os.path.join(work, "guess.json"), "--data", os.path.join(work, "targets.csv"),
               "--smooth", "1e-4", "--optimizer", "nlopt:LD_LBFGS"]
    for j in range(knots):
        command += ["--param", f"/effects/1/schedule/values/{j}/0"]
    results = {}
    for method in ("jet", "adjoint"):
        seconds, outputs = [], []
        for _ in range(args.runs):
            start = time.monotonic()
            done = subprocess.run(command + ["--method", method], capture_output=True, text=True)
            seconds.append(time.monotonic() - start)
            if done.returncode not in (0, 1):
                sys.exit(f"fit --method {method} exited {done.returncode}: {done.stderr[-400:]}")
            outputs.append(json.loads(done.stdout))
        results[method] = (statistics.median(seconds), outputs[0])
    for method, (seconds, out) in results.items():
        print(f"--method {method}: {seconds:.2f} s wall (median of {args.runs}), final cost {out['final_cost']:.6g} "
              f"from {out['initial_cost']:.6g}, {out['evaluations']} evaluations, gradient_method "
              f"{out['gradient_method']}")
    print(f"{knots} knots: the adjoint fit takes {results['jet'][0] / results['adjoint'][0]:.1f} times less wall "
          f"time than the Jets'")


if __name__ == "__main__":
    main(sys.argv[1:])
