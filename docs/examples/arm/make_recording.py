#!/usr/bin/env python3
"""Makes guess.json and encoders.csv, the 3D identification example of the README (standard library only).

    python3 docs/examples/arm/make_recording.py [--tether build/tether]

A two-link arm in 3D: the upper link (1 kg, 0.6 m) turns about the vertical on a world hinge (the shoulder, with
viscous damping) and carries the lower link on a horizontal hinge (the elbow); both are rods of 2 cm radius.
Released turning about the vertical at 1 rad/s as one body, the forearm 0.8 rad below the horizontal, it swings
under gravity. The truth has a 0.7 kg forearm (its moments of inertia those of the same rod at that mass) and
a shoulder damping of 0.15 N m s/rad; it is simulated for 3 s by rk45 at h = 1e-3 (another integrator and step
than the one fitted) and recorded by the two joint encoders every 20 ms with Gaussian noise of 0.5 mrad (seed 1).
guess.json has a 1 kg forearm with the moments of a 1 kg rod, a damping of 0.05 and rk4 at h = 1e-3: the
unknowns are the forearm's mass, its two transverse moments and the damping.
"""
import argparse, csv, json, os, random, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")
sys.path.insert(0, os.path.join(ROOT, "scenes"))
from make_3d_scenes import qaxis, qmul, qrot as rotate, rod  # noqa: E402  (the shipped scenes' helpers)


def arm(forearm_mass, damping, integrator):
    length = 0.6
    q1 = qaxis([0, 0, 1], 0.3)
    q2 = qmul(qaxis([0, 1, 0], -0.8), q1)
    elbow = rotate(q1, [length, 0, 0])
    centre = [elbow[k] + rotate(q2, [length / 2, 0, 0])[k] for k in range(3)]
    upper = rotate(q1, [length / 2, 0, 0])
    return {"dimension": 3,
            "bodies": [{"name": "upper", "type": "rigid", "mass": 1.0, "inertia": rod(1.0, length),
                        "position": upper, "orientation": q1, "velocity": [-upper[1], upper[0], 0.0],
                        "angular_velocity": [0, 0, 1]},
                       {"name": "forearm", "type": "rigid", "mass": forearm_mass, "inertia": rod(forearm_mass, length),
                        "position": centre, "orientation": q2, "velocity": [-centre[1], centre[0], 0.0],
                        "angular_velocity": [0, 0, 1]}],
            "constraints": [{"type": "hinge", "name": "shoulder", "bodies": ["world", "upper"],
                             "points": [[0, 0, 0], [-length / 2, 0, 0]], "axis": [0, 0, 1]},
                            {"type": "hinge", "name": "elbow", "bodies": ["upper", "forearm"],
                             "points": [[length / 2, 0, 0], [-length / 2, 0, 0]], "axis": [0, 1, 0]}],
            "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]},
                        {"type": "joint_spring", "joint": "shoulder", "stiffness": 0.0, "damping": damping}],
            "markers": [{"name": "hand", "body": "forearm", "point": [length / 2, 0, 0]}],
            "simulation": {"integrator": integrator, "step": 1e-3, "duration": 3.0}}


ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()
with tempfile.TemporaryDirectory() as work:
    json.dump(arm(0.7, 0.15, "rk45"), open(os.path.join(work, "truth.json"), "w"))
    subprocess.run([args.tether, "simulate", os.path.join(work, "truth.json"), "--every", "20", "-o",
                    os.path.join(work, "truth.csv")], check=True)
    rows = list(csv.DictReader(open(os.path.join(work, "truth.csv"))))
random.seed(1)
columns = ["shoulder.angle", "elbow.angle"]
with open(os.path.join(HERE, "encoders.csv"), "w") as f:
    f.write(",".join(["t"] + columns) + "\n")
    for r in rows[1:]:
        f.write(",".join([r["t"]] + ["%.7f" % (float(r[c]) + random.gauss(0.0, 5e-4)) for c in columns]) + "\n")
json.dump(arm(1.0, 0.05, "rk4"), open(os.path.join(HERE, "guess.json"), "w"), indent=1)
