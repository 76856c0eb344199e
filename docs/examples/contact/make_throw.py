#!/usr/bin/env python3
"""Makes the README's throw (standard library only):

    python3 docs/examples/contact/make_throw.py [--tether build/tether]

throw.json: a ball (a 0.5 kg particle with a sphere of radius 0.1 m, restitution 0.6, friction 0.3) thrown from 1 m
at (2, 0, 1) m/s onto a floor, 1 s. basket.csv: where the throw (2.5, 0, 1.8) m/s puts it at t = 1 s, after one
bounce. `tether fit` then finds the throw that lands the ball in the basket from throw.json's, derivatives by Jets
through the impact (whose time moves with the vertical speed); the script prints the impact and the fit.
"""
import argparse, copy, csv, json, os, subprocess, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")

ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()

throw = {"dimension": 3,
         "bodies": [{"name": "ball", "type": "particle", "mass": 0.5, "position": [0.0, 0.0, 1.0],
                     "velocity": [2.0, 0.0, 1.0]}],
         "shapes": [{"name": "ball_surface", "body": "ball", "type": "sphere", "radius": 0.1, "restitution": 0.6,
                     "friction": 0.3},
                    {"name": "floor", "body": "world", "type": "plane"}],
         "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}],
         "simulation": {"integrator": "rk4", "step": 0.001, "duration": 1.0}}
with open(os.path.join(HERE, "throw.json"), "w") as f:
    json.dump(throw, f, indent=1)
    f.write("\n")

with tempfile.TemporaryDirectory() as work:
    truth = copy.deepcopy(throw)
    truth["bodies"][0]["velocity"] = [2.5, 0.0, 1.8]
    truth_path, run_csv, events_csv = (os.path.join(work, n) for n in ("truth.json", "truth.csv", "events.csv"))
    json.dump(truth, open(truth_path, "w"))
    subprocess.run([args.tether, "simulate", truth_path, "-o", run_csv, "--events", events_csv], check=True)
    print("truth's events:", ", ".join("%s at %.4f s" % (e["kind"], float(e["t"]))
                                       for e in csv.DictReader(open(events_csv))))
    end = list(csv.DictReader(open(run_csv)))[-1]
    with open(os.path.join(HERE, "basket.csv"), "w") as f:
        f.write("t,ball.x,ball.z\n%s,%s,%s\n" % (end["t"], end["ball.x"], end["ball.z"]))
result = subprocess.run([args.tether, "fit", os.path.join(HERE, "throw.json"), "--data",
                         os.path.join(HERE, "basket.csv"), "--param", "/bodies/0/velocity/0", "--param",
                         "/bodies/0/velocity/2"], check=True, capture_output=True, text=True).stdout
print(json.dumps({k: json.loads(result)[k] for k in ("parameters", "initial_cost", "final_cost", "evaluations")},
                 indent=1))
