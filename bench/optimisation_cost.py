#!/usr/bin/env python3
"""What the optimisations users wait for cost, each as a multiple of one plain simulation of its scene, both timed
in this one process (issue 38, part 5; README "Fit a trajectory", docs/performance.md):

    /usr/bin/python3 bench/optimisation_cost.py [--build build] [--only NAME]

  acrobot     README's swing-up: scenes/acrobot.json, 41 elbow-torque knots, the tip within 9 mm of straight above
              the shoulder written as the shoulder's angle and the tip's offset, 8 starts (swing_up.py's flags,
              --form angle);
  acrobot_tip the same swing-up as a user first writes it: the tip's height at least 1.99 m, its offset within
              1 cm, effort 1e-3, 8 starts (--form height);
  humanoid    README's identification of MuJoCo's humanoid's left forearm mass from its five joint encoders
              (docs/examples/humanoid; needs Debian's libmujoco-samples for the model).

--build names the build whose Python module is timed (its python/ folder and its tether, which imports the
humanoid), so that two builds can be compared one after the other on the same machine. A plain simulation is the
median of 21 runs of Scene.simulate() with the scene's own settings (the identification's: 3 s); an optimisation
runs once. Prints one line per task: wall seconds, the plain simulation's milliseconds, their ratio, and what the
optimisation reached.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT, "docs", "examples", "acrobot"))
import swing_up  # noqa: E402  (the two forms' flags, as swing_up.py runs them)

HUMANOID = "/usr/share/mujoco/model/humanoid/humanoid.xml"


def plain_seconds(scene):
    times = []
    for _ in range(21):
        begin = time.perf_counter()
        scene.simulate()
        times.append(time.perf_counter() - begin)
    return statistics.median(times)


def fit_arguments(flags):
    """tether.fit's keyword arguments for swing_up.py's command-line flags of one form."""
    arguments = {"params": [], "bounds": {}, "at_least": [], "at_most": []}
    for flag, value in zip(flags[::2], flags[1::2]):
        if flag == "--param":
            arguments["params"].append(value)
        elif flag == "--bound":
            pointer, interval = value.rsplit("=", 1)
            arguments["bounds"][pointer] = tuple(float(b) for b in interval.split(":"))
        elif flag in ("--at-least", "--at-most"):
            arguments[flag[2:].replace("-", "_")].append(value)
        elif flag == "--effort":
            arguments["effort"] = float(value)
        elif flag == "--starts":
            arguments["starts"] = int(value)
        else:
            raise ValueError("swing_up.py's flag %s has no counterpart here" % flag)
    return arguments


def acrobot(tether, form):
    scene = tether.Scene.load(os.path.join(ROOT, "scenes", "acrobot.json"))
    arguments = fit_arguments(swing_up.FLAGS[form])
    begin = time.perf_counter()
    report = tether.fit(scene, None, **arguments)
    seconds = time.perf_counter() - begin
    reached = "%d of %d starts feasible, cost %.4f" % (report["starts"]["feasible"], report["starts"]["count"],
                                                       report["final_cost"])
    return seconds, plain_seconds(scene), reached


def humanoid(tether, build):
    if not os.path.exists(HUMANOID):
        return None
    work = tempfile.mkdtemp(prefix="tether_optimisation_cost_")
    path = os.path.join(work, "humanoid.json")
    subprocess.run([os.path.join(build, "tether"), "import", HUMANOID, "--fix", "torso", "--no-contact",
                    "--joint-velocity", "left_elbow=2", "--joint-velocity", "right_knee=-1.5", "-o", path],
                   check=True, capture_output=True)
    document = tether.Scene.load(path).to_dict()
    document.setdefault("simulation", {})["duration"] = 3.0  # the recording's length
    scene = tether.Scene.from_dict(document, path)
    import pandas
    table = pandas.read_csv(os.path.join(ROOT, "docs", "examples", "humanoid", "joint_angles.csv"))
    data = {column: table[column].to_numpy() for column in table.columns}
    begin = time.perf_counter()
    report = tether.identify(scene, data, ["/bodies/12/mass"])
    seconds = time.perf_counter() - begin
    reached = "mass %.5f kg, %d evaluations" % (report["parameters"]["/bodies/12/mass"], report["evaluations"])
    return seconds, plain_seconds(scene), reached


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--only", choices=["acrobot", "acrobot_tip", "humanoid"])
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(os.path.abspath(args.build), "python"))
    import tether
    tasks = {"acrobot": lambda: acrobot(tether, "angle"), "acrobot_tip": lambda: acrobot(tether, "height"),
             "humanoid": lambda: humanoid(tether, args.build)}
    for name, task in tasks.items():
        if args.only and name != args.only:
            continue
        measured = task()
        if measured is None:
            print("%-12s skipped: %s is missing (apt-get install libmujoco-samples)" % (name, HUMANOID))
            continue
        seconds, plain, reached = measured
        print("%-12s %7.2f s  plain simulation %8.3f ms  %9.0f x  %s" %
              (name, seconds, 1e3 * plain, seconds / plain, reached), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
