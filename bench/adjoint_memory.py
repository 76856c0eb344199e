#!/usr/bin/env python3
"""A gradient over 10^6 steps by the adjoint, in bounded memory (issue 17): what it kept, what the process
used, and what it cost against the plain simulation.

    python3 bench/adjoint_memory.py [--tether build/tether] [--steps 1000000]

The scene: fit_knots.py's planar chain of 10 particles (0.1 kg on 0.1 m links) hanging from the origin, its end pushed
sideways at 0.3 m/s, with light damping, rk4 at h = 1 ms for STEPS steps; the data are the end's position at
four times, shifted by 1 cm. Runs `tether simulate` (the plain run) and `tether gradient --method adjoint` with
three parameters, and prints the adjoint's report (steps, the checkpoint interval K, the states kept and the
bytes it counts), the gradient process's peak resident memory (getrusage), and both wall times. About a minute
with the defaults. Standard library only.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import fit_knots
from fit_knots import LINKS

def scene(duration):
    """fit_knots.py's chain without its force schedule, its end pushed sideways, lightly damped."""
    document = fit_knots.scene([0.0, 0.0], 2)
    document["effects"] = [document["effects"][0], {"type": "damping", "coefficient": 0.05}]
    document["bodies"][-1]["velocity"] = [0.3, 0.0]
    document["simulation"]["duration"] = duration
    return document


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tether", default="build/tether")
    parser.add_argument("--steps", type=int, default=1000000)
    args = parser.parse_args(argv)
    work = tempfile.mkdtemp(prefix="tether-adjoint-memory-")
    duration = args.steps * 1e-3
    path = os.path.join(work, "chain.json")
    with open(path, "w") as f:
        json.dump(scene(duration), f)
    start = time.monotonic()
    out = subprocess.run([args.tether, "simulate", path, "--every", str(args.steps // 4)], capture_output=True,
                         text=True, check=True).stdout.splitlines()
    plain = time.monotonic() - start
    header = out[0].split(",")
    end = f"p{LINKS - 1}"
    columns = [header.index("t"), header.index(end + ".x"), header.index(end + ".y")]
    data = os.path.join(work, "data.csv")
    with open(data, "w") as f:
        f.write(f"t,{end}.x,{end}.y\n")
        for line in out[2:]:
            cells = line.split(",")
            f.write(",".join([cells[columns[0]]] + [repr(float(cells[c]) + 0.01) for c in columns[1:]]) + "\n")
    start = time.monotonic()
    done = subprocess.run([args.tether, "gradient", path, "--data", data, "--param", f"/bodies/{LINKS - 1}/mass",
                           "--param", "/constraints/0/length", "--param", "/effects/1/coefficient", "--method",
                           "adjoint"], capture_output=True, text=True, check=True)
    seconds = time.monotonic() - start
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024  # KiB -> MiB, the largest child
    report = json.loads(done.stdout)["adjoint"]
    print(f"{report['steps']} steps: a checkpoint every {report['interval']} steps, {report['checkpoints']} kept, "
          f"{report['memory_bytes'] / 2**20:.0f} MiB counted (the budget is 256 MiB); peak resident memory of the "
          f"gradient process {peak:.0f} MiB")
    print(f"plain simulation {plain:.1f} s, adjoint gradient {seconds:.1f} s wall ({seconds / plain:.1f}x)")


if __name__ == "__main__":
    main(sys.argv[1:])
