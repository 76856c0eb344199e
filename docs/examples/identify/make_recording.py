#!/usr/bin/env python3
"""Makes recording.csv, the worked identification example of the README (standard library only).

    python3 docs/examples/identify/make_recording.py [--tether build/tether]

The truth is scenes/double_pendulum.json with a 2 kg outer bob, simulated for 6 s by rk45 at h = 1e-3 (another
integrator and step than the one fitted), sampled every 20 ms, with Gaussian noise of 1 mm on every position
(seed 1): a chaotic motion recorded as a tracker would. guess.json is the same scene with a 1.3 kg guess.
"""
import argparse, csv, json, os, random, subprocess, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")

ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()
scene = json.load(open(os.path.join(ROOT, "scenes", "double_pendulum.json")))
scene["simulation"].update({"duration": 6.0, "integrator": "rk45", "step": 1e-3})
truth = json.loads(json.dumps(scene))
truth["bodies"][1]["mass"] = 2.0
with tempfile.TemporaryDirectory() as work:
    json.dump(truth, open(os.path.join(work, "truth.json"), "w"))
    subprocess.run([args.tether, "simulate", os.path.join(work, "truth.json"), "--every", "20", "-o",
                    os.path.join(work, "truth.csv")], check=True)
    rows = list(csv.DictReader(open(os.path.join(work, "truth.csv"))))
random.seed(1)
columns = ["p0.x", "p0.y", "p1.x", "p1.y"]
with open(os.path.join(HERE, "recording.csv"), "w") as f:
    f.write(",".join(["t"] + columns) + "\n")
    for r in rows:
        f.write(",".join([r["t"]] + ["%.6f" % (float(r[c]) + random.gauss(0.0, 1e-3)) for c in columns]) + "\n")
guess = json.loads(json.dumps(scene))
guess["bodies"][1]["mass"] = 1.3
guess["simulation"].update({"integrator": "rk4", "step": 2e-3})
json.dump(guess, open(os.path.join(HERE, "guess.json"), "w"), indent=2)
