#!/usr/bin/env python3
"""Makes arm.json, guess.json and joint_angles.csv, the servo examples of the README (standard library only).

    python3 docs/examples/servo/make_recording.py [--tether build/tether]

A two-link SCARA arm: two 0.4 m rods of 1 kg and 0.6 kg on hinges about the vertical (gravity is carried by the
hinges), each joint driven by a position servo (joint_servo) towards the pose shoulder 1.0 rad, elbow -1.5 rad,
its target ramped there over the first second, the shoulder's torque saturated at 8 N m. arm.json is that arm
(kp 40 and 20 N m/rad, kd 6 and 2 N m s/rad): it reaches the pose. The recording is the truth (arm.json run by
rk45 at h = 1e-3, another integrator than the one fitted) seen by the two joint encoders every 10 ms for 3 s with
Gaussian noise of 0.5 mrad (seed 2). guess.json has the gains 30% off (kp 28 and 26, kd 7.8 and 1.4) and rk4:
the unknowns are the four gains.
"""
import argparse, csv, json, os, random, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")
sys.path.insert(0, os.path.join(ROOT, "scenes"))
from make_3d_scenes import rod  # noqa: E402  (the shipped scenes' helpers)

LENGTH = 0.4


def arm(gains, integrator):
    (kp1, kd1), (kp2, kd2) = gains
    ramp = {"times": [0.0, 0.1], "values": [0.0, 1.0]}
    elbow_ramp = {"times": [0.0, 0.1], "values": [0.0, -1.5]}
    return {"dimension": 3,
            "bodies": [{"name": "upper", "type": "rigid", "mass": 1.0, "inertia": rod(1.0, LENGTH),
                        "position": [LENGTH / 2, 0, 0]},
                       {"name": "forearm", "type": "rigid", "mass": 0.6, "inertia": rod(0.6, LENGTH),
                        "position": [1.5 * LENGTH, 0, 0]}],
            "constraints": [{"type": "hinge", "name": "shoulder", "bodies": ["world", "upper"],
                             "points": [[0, 0, 0], [-LENGTH / 2, 0, 0]], "axis": [0, 0, 1]},
                            {"type": "hinge", "name": "elbow", "bodies": ["upper", "forearm"],
                             "points": [[LENGTH / 2, 0, 0], [-LENGTH / 2, 0, 0]], "axis": [0, 0, 1]}],
            "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]},
                        {"type": "joint_servo", "joint": "shoulder", "kp": kp1, "kd": kd1, "schedule": ramp,
                         "limit": 8.0},
                        {"type": "joint_servo", "joint": "elbow", "kp": kp2, "kd": kd2, "schedule": elbow_ramp}],
            "markers": [{"name": "hand", "body": "forearm", "point": [LENGTH / 2, 0, 0]}],
            "simulation": {"integrator": integrator, "step": 1e-3, "duration": 3.0}}


ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()
truth = arm([(40.0, 6.0), (20.0, 2.0)], "rk4")
json.dump(truth, open(os.path.join(HERE, "arm.json"), "w"), indent=1)
with tempfile.TemporaryDirectory() as work:
    truth["simulation"]["integrator"] = "rk45"
    json.dump(truth, open(os.path.join(work, "truth.json"), "w"))
    subprocess.run([args.tether, "simulate", os.path.join(work, "truth.json"), "--every", "10", "-o",
                    os.path.join(work, "truth.csv")], check=True)
    rows = list(csv.DictReader(open(os.path.join(work, "truth.csv"))))
random.seed(2)
columns = ["shoulder.angle", "elbow.angle"]
with open(os.path.join(HERE, "joint_angles.csv"), "w") as f:
    f.write(",".join(["t"] + columns) + "\n")
    for r in rows[1:]:
        f.write(",".join([r["t"]] + ["%.7f" % (float(r[c]) + random.gauss(0.0, 5e-4)) for c in columns]) + "\n")
json.dump(arm([(28.0, 7.8), (26.0, 1.4)], "rk4"), open(os.path.join(HERE, "guess.json"), "w"), indent=1)
