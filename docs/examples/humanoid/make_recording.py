#!/usr/bin/env python3
"""Makes joint_angles.csv, the humanoid identification example of the README (standard library only).

    python3 docs/examples/humanoid/make_recording.py [--tether build/tether] [--model PATH]

MuJoCo's humanoid (Debian's libmujoco-samples), imported by `tether import` hanging by its torso, its left elbow
and right knee started at 2 and -1.5 rad/s (the README's import command). The truth carries a weight of 0.35 kg
strapped at the left forearm's centre of mass (its mass 0.961 -> 1.311 kg, its inertia about that point the
same); it is simulated for 3 s by rk45 (another integrator than the one fitted) and recorded by the five joint
encoders the scene has (abdomen_x, both knees, both elbows) every 20 ms with Gaussian noise of 0.5 mrad (seed 1).
Then `tether identify` on the imported scene (MuJoCo's forearm, rk4 at MuJoCo's 5 ms) estimates the forearm's
mass from the recording; the script prints its JSON, which the README quotes.
"""
import argparse, csv, json, os, random, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")
WEIGHT = 0.35  # kg, at the forearm's centre of mass
DURATION = 3.0
COLUMNS = ["abdomen_x.angle", "right_knee.angle", "left_knee.angle", "right_elbow.angle", "left_elbow.angle"]


def run(*command):
    return subprocess.run(command, check=True, capture_output=True, text=True).stdout


ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
ap.add_argument("--model", default="/usr/share/mujoco/model/humanoid/humanoid.xml")
args = ap.parse_args()
with tempfile.TemporaryDirectory() as work:
    scene_path = os.path.join(work, "humanoid.json")
    run(args.tether, "import", args.model, "--fix", "torso", "--no-contact", "--joint-velocity", "left_elbow=2",
        "--joint-velocity", "right_knee=-1.5", "-o", scene_path)
    scene = json.load(open(scene_path))
    forearm = [b["name"] for b in scene["bodies"]].index("left_lower_arm")
    scene["bodies"][forearm]["mass"] += WEIGHT
    scene["simulation"].update({"integrator": "rk45", "duration": DURATION})
    truth_path = os.path.join(work, "truth.json")
    json.dump(scene, open(truth_path, "w"))
    run(args.tether, "simulate", truth_path, "--step", "0.001", "--every", "20", "-o", os.path.join(work, "truth.csv"))
    rows = list(csv.DictReader(open(os.path.join(work, "truth.csv"))))
    random.seed(1)
    recording = os.path.join(HERE, "joint_angles.csv")
    with open(recording, "w") as f:
        f.write(",".join(["t"] + COLUMNS) + "\n")
        for r in rows[1:]:
            f.write(",".join([r["t"]] + ["%.7f" % (float(r[c]) + random.gauss(0.0, 5e-4)) for c in COLUMNS]) + "\n")
    print(run(args.tether, "identify", scene_path, "--duration", str(DURATION), "--data", recording,
              "--param", "/bodies/%d/mass" % forearm), end="")
