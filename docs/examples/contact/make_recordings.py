#!/usr/bin/env python3
"""Makes the contact identification example of the README (standard library only):

    python3 docs/examples/contact/make_recordings.py [--tether build/tether]

ball.json, ball_guess.json, bounces.csv: a ball (a 1 kg particle with a sphere of radius 0.05 m) dropped from 1 m
onto a floor; the truth's restitution is 0.8 (four impacts in 2.5 s), the guess's 0.6.
block.json, block_guess.json, slide.csv: a block (a 1 kg cube of 0.1 m) launched at 2 m/s along a floor; the
truth's friction is 0.35 (it slides to rest in 0.58 s and stays), the guess's 0.25.
Each truth is simulated by rk45 at a tight tolerance (another integrator than the one fitted) and recorded every
10 ms with Gaussian noise of 1 mm (seeds 1 and 2); then `tether identify` estimates the restitution and the
friction from the recordings, derivatives by Jets through the impacts and the stop. The script prints the
events of each truth and the two results, which the README quotes.
"""
import argparse, copy, csv, json, os, random, subprocess, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")

ap = argparse.ArgumentParser()
ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
args = ap.parse_args()

ball = {"dimension": 3,
        "bodies": [{"name": "ball", "type": "particle", "mass": 1.0, "position": [0.0, 0.0, 1.05]}],
        "shapes": [{"name": "ball_surface", "body": "ball", "type": "sphere", "radius": 0.05, "restitution": 0.8},
                   {"name": "floor", "body": "world", "type": "plane"}],
        "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}],
        "simulation": {"integrator": "rk4", "step": 0.001, "duration": 2.5}}
block = {"dimension": 3,
         "bodies": [{"name": "block", "type": "rigid", "mass": 1.0, "inertia": [0.02 / 12] * 3,
                     "position": [0.0, 0.0, 0.05], "velocity": [2.0, 0.0, 0.0]}],
         "shapes": [{"name": "cube", "body": "block", "type": "box", "size": [0.1, 0.1, 0.1], "friction": 0.35},
                    {"name": "floor", "body": "world", "type": "plane"}],
         "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}],
         "simulation": {"integrator": "rk4", "step": 0.001, "duration": 1.0}}
cases = [("ball", ball, "/shapes/0/restitution", 0.6, "bounces.csv", "ball.z", 1),
         ("block", block, "/shapes/0/friction", 0.25, "slide.csv", "block.x", 2)]

with tempfile.TemporaryDirectory() as work:
    for name, scene, pointer, guess_value, recording, column, seed in cases:
        guess = copy.deepcopy(scene)
        guess["shapes"][0][pointer.split("/")[-1]] = guess_value
        for file, document in ((name + ".json", scene), (name + "_guess.json", guess)):
            with open(os.path.join(HERE, file), "w") as f:
                json.dump(document, f, indent=1)
                f.write("\n")
        truth = copy.deepcopy(scene)
        truth["simulation"].update({"integrator": "rk45", "tolerance": 1e-12})
        truth_path = os.path.join(work, name + "_truth.json")
        json.dump(truth, open(truth_path, "w"))
        run_csv, events_csv = os.path.join(work, name + ".csv"), os.path.join(work, name + "_events.csv")
        subprocess.run([args.tether, "simulate", truth_path, "--every", "10", "-o", run_csv, "--events", events_csv],
                       check=True)
        events = [(e["kind"], float(e["t"])) for e in csv.DictReader(open(events_csv))]
        print(name, "truth's events:", ", ".join("%s at %.4f s" % e for e in events))
        random.seed(seed)
        with open(os.path.join(HERE, recording), "w") as f:
            f.write("t,%s\n" % column)
            for r in list(csv.DictReader(open(run_csv)))[1:]:
                f.write("%s,%.7f\n" % (r["t"], float(r[column]) + random.gauss(0.0, 1e-3)))
        print(subprocess.run([args.tether, "identify", os.path.join(HERE, name + "_guess.json"), "--data",
                              os.path.join(HERE, recording), "--param", pointer],
                             check=True, capture_output=True, text=True).stdout, end="")
