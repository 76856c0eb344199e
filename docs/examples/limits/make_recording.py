#!/usr/bin/env python3
"""Makes stop.json, guess.json and bounces.csv, the joint-limit identification example of the README (standard
library only).

    python3 docs/examples/limits/make_recording.py [--tether build/tether]

A uniform rod (1 kg, 1 m) hangs by a named pin, `hinge`, at its end and is released at rest 60 degrees from the
vertical; the pin's range [0, null] puts a stop at the vertical. The truth's stop has restitution 0.75: the rod
swings into it and bounces back lower each time, four impacts in 3 s. It is simulated by rk45 at a tight tolerance
(another integrator than the one fitted) and recorded by the hinge's encoder every 10 ms with Gaussian noise of
0.5 mrad (seed 1). Then `tether identify` on guess.json (restitution 0.5, rk4 at 1 ms) estimates the restitution
from the recording, derivatives by Jets through the impacts; the script prints its JSON, which the README quotes.
"""
import argparse, copy, csv, json, math, os, random, subprocess, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")
TRUTH, GUESS = 0.75, 0.5
THETA0 = math.pi / 3

ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()

a = -math.pi / 2 + THETA0
scene = {"dimension": 2,
         "bodies": [{"name": "rod", "type": "rigid", "mass": 1.0, "inertia": 1.0 / 12.0,
                     "position": [0.5 * math.cos(a), 0.5 * math.sin(a)], "angle": a}],
         "constraints": [{"type": "pin", "name": "hinge", "bodies": ["world", "rod"],
                          "points": [[0.0, 0.0], [-0.5, 0.0]], "angle": THETA0, "range": [0.0, None],
                          "restitution": TRUTH}],
         "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
         "simulation": {"integrator": "rk4", "step": 0.001, "duration": 3.0}}
guess = copy.deepcopy(scene)
guess["constraints"][0]["restitution"] = GUESS
for name, document in (("stop.json", scene), ("guess.json", guess)):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(document, f, indent=1)
        f.write("\n")
with tempfile.TemporaryDirectory() as work:
    truth = copy.deepcopy(scene)
    truth["simulation"].update({"integrator": "rk45", "tolerance": 1e-12})
    truth_path = os.path.join(work, "truth.json")
    json.dump(truth, open(truth_path, "w"))
    run_csv, events_csv = os.path.join(work, "truth.csv"), os.path.join(work, "events.csv")
    subprocess.run([args.tether, "simulate", truth_path, "--every", "10", "-o", run_csv, "--events", events_csv],
                   check=True)
    impacts = sum(1 for e in csv.DictReader(open(events_csv)) if e["kind"] == "impact")
    rows = list(csv.DictReader(open(run_csv)))
    random.seed(1)
    recording = os.path.join(HERE, "bounces.csv")
    with open(recording, "w") as f:
        f.write("t,hinge.angle\n")
        for r in rows[1:]:
            f.write("%s,%.7f\n" % (r["t"], float(r["hinge.angle"]) + random.gauss(0.0, 5e-4)))
print("impacts in the truth:", impacts)
print(subprocess.run([args.tether, "identify", os.path.join(HERE, "guess.json"), "--data", recording,
                      "--param", "/constraints/0/restitution"], check=True, capture_output=True, text=True).stdout,
      end="")
