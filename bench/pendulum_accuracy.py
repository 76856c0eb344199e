#!/usr/bin/env python3
"""Accuracy of each integrator on the shipped pendulum (scenes/pendulum.json), against the exact solution.

    python3 bench/pendulum_accuracy.py [--tether build/tether]

Released from rest at theta0, a pendulum of length L follows sin(theta/2) = k sn(K(k) - w t, k) with
k = sin(theta0/2), w = sqrt(g/L) (Jacobi's elliptic sn, computed here by the descending Landen/AGM scheme).
For each integrator and step the script runs `tether simulate`, and prints a Markdown table of the bob's
position error at the end of the run, the largest constraint error and the relative energy drift.
Standard library only.
"""
import argparse, csv, json, math, os, subprocess, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def agm_terms(m):
    a, b, c = [1.0], [math.sqrt(1.0 - m)], [math.sqrt(m)]
    while abs(c[-1]) > 1e-16:
        an, bn = a[-1], b[-1]
        a.append((an + bn) / 2)
        b.append(math.sqrt(an * bn))
        c.append((an - bn) / 2)
    return a, c


def complete_k(m):
    a, _ = agm_terms(m)
    return math.pi / (2 * a[-1])


def jacobi_sn(u, m):
    a, c = agm_terms(m)
    n = len(a) - 1
    phi = 2 ** n * a[n] * u
    for i in range(n, 0, -1):
        phi = (phi + math.asin(c[i] / a[i] * math.sin(phi))) / 2
    return math.sin(phi)


def exact_bob(t, length, theta0, g):
    k = math.sin(theta0 / 2)
    w = math.sqrt(g / length)
    theta = 2 * math.asin(k * jacobi_sn(complete_k(k * k) - w * t, k * k))
    return length * math.sin(theta), -length * math.cos(theta)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tether", default=os.path.join(HERE, "..", "build", "tether"))
    ap.add_argument("--scene", default=os.path.join(HERE, "..", "scenes", "pendulum.json"))
    args = ap.parse_args()
    scene = json.load(open(args.scene))
    x0, y0 = scene["bodies"][0]["position"]
    length = math.hypot(x0, y0)
    theta0 = math.atan2(x0, -y0)
    g = -scene["effects"][0]["acceleration"][1]
    duration = scene["simulation"]["duration"]
    runs = [("euler", 1e-4), ("euler", 1e-5), ("symplectic_euler", 1e-3), ("symplectic_euler", 1e-4),
            ("rk4", 1e-2), ("rk4", 1e-3), ("rk45", 1e-2), ("rk45", 1e-3)]
    print(f"Pendulum: L = {length:g} m, released from {math.degrees(theta0):.0f} degrees, {duration:g} s, "
          "default gains; error of the bob's position at the end against the exact solution.\n")
    print("| integrator | h (s) | position error (m) | max constraint error (m) | energy drift (relative) |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        out = os.path.join(work, "run.csv")
        for integrator, step in runs:
            every = max(1, int(round(0.01 / step)))
            subprocess.run([args.tether, "simulate", args.scene, "--integrator", integrator, "--step", repr(step),
                            "--every", str(every), "-o", out], check=True)
            rows = list(csv.DictReader(open(out)))
            last = rows[-1]
            ex, ey = exact_bob(float(last["t"]), length, theta0, g)
            err = math.hypot(float(last["bob.x"]) - ex, float(last["bob.y"]) - ey)
            e0 = float(rows[0]["energy"])
            drift = max(abs(float(r["energy"]) - e0) for r in rows) / abs(e0)
            cmax = max(float(r["constraint_error"]) for r in rows)
            print(f"| {integrator} | {step:g} | {err:.1e} | {cmax:.1e} | {drift:.1e} |")


if __name__ == "__main__":
    main()
