#!/usr/bin/env python3
"""Tuned Baumgarte gains against the presets on the shipped scenes, as a Markdown table for the README.

    python3 bench/tune_table.py [--tether build/tether]

For each of scenes/pendulum.json, double_pendulum.json and four_bar.json at h = 1e-2 and 1e-3 s (their own
integrator, rk4, and duration), runs `tether tune` (reference objective, Ceres) and prints, for the tuned gains
and each preset, the RMS position error against the reference over the whole run and the largest constraint
violation. Standard library only.
"""
import argparse, json, os, subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tether", default=os.path.join(HERE, "..", "build", "tether"))
    args = ap.parse_args()
    print("| scene | h (s) | tuned alpha, beta | tuned | none (0, 0) | RBDL (20, 100) | MuJoCo (100, 2500) | tuning time (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in ("pendulum", "double_pendulum", "four_bar"):
        for step in ("1e-2", "1e-3"):
            path = os.path.join(HERE, "..", "scenes", scene + ".json")
            out = subprocess.run([args.tether, "tune", path, "--step", step], capture_output=True, text=True, check=True)
            result = json.loads(out.stdout)
            rows = {row["name"]: row for row in result["comparison"]}

            def cell(name):
                row = rows[name]
                if row["diverged"]:
                    return "diverges"
                return f"{row['rms_position_error']:.1e} / {row['max_constraint_error']:.1e}"

            print(f"| {scene} | {step} | {result['alpha']:.3g}, {result['beta']:.3g} | {cell('tuned')} | {cell('none')} | "
                  f"{cell('rbdl')} | {cell('mujoco')} | {result['seconds']:.1f} |")
    print("\nEach cell: RMS position error against the reference / largest constraint violation, in metres, over the "
          "whole run.")


if __name__ == "__main__":
    main()
