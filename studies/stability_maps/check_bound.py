"""Checks the stability map against the linear theory, independently of tether's own stability code.

    python3 studies/stability_maps/check_bound.py [RESULTS.csv]

For every run of the stability map (studies/stability_maps/results/results.csv by default) the constraint error
obeys C'' + alpha C' + beta C = 0; with omega = sqrt(beta), zeta = alpha / (2 omega) and x = h omega, one step of
the integrator multiplies (C, C'/omega) by the amplification matrix M (tuning/include/tether/tuning/stability.h):
    rk4               M = sum_{k<=4} (x K)^k / k!,  K = [[0, 1], [-1, -2 zeta]]
    symplectic_euler  M = [[1 - x^2, x (1 - 2 zeta x)], [-x, 1 - 2 zeta x]]
The run is predicted stable when the spectral radius of M is at most 1, and a run stayed bounded unless it
diverged: a `drifted` run (constraints more than 1% of the length scale off, within the scale itself) is
bounded but weakly corrected, and counted apart. Prints how many runs agree with the prediction and lists those
that do not; the README quotes these lines.
"""
import cmath
import csv
import math
import os
import sys


def product(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(2)) for j in range(2)] for i in range(2)]


def amplification(integrator, x, zeta):
    if integrator == "symplectic_euler":
        return [[1 - x * x, x * (1 - 2 * zeta * x)], [-x, 1 - 2 * zeta * x]]
    z = [[0.0, x], [-x, -2 * zeta * x]]
    total, power = [[1.0, 0.0], [0.0, 1.0]], [[1.0, 0.0], [0.0, 1.0]]
    for k in range(1, 5):
        power = [[v / k for v in row] for row in product(power, z)]
        total = [[total[i][j] + power[i][j] for j in range(2)] for i in range(2)]
    return total


def radius(m):
    trace, det = m[0][0] + m[1][1], m[0][0] * m[1][1] - m[0][1] * m[1][0]
    root = cmath.sqrt(trace * trace - 4 * det)
    return max(abs((trace + root) / 2), abs((trace - root) / 2))


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results", "results.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    agree, stable_bounded, unstable_diverged, drifted, disagreements = 0, 0, 0, 0, []
    for r in rows:
        alpha, beta, h = float(r["/stabilization/alpha"]), float(r["/stabilization/beta"]), float(r["/simulation/step"])
        omega = math.sqrt(beta)
        rho = radius(amplification(r["/simulation/integrator"], h * omega, alpha / (2 * omega)))
        diverged = r["status"].startswith("diverged")
        if (rho <= 1 + 1e-12) != diverged:
            agree += 1
            stable_bounded += not diverged
            unstable_diverged += diverged
            drifted += r["status"].startswith("drifted")
        else:
            disagreements.append((r, rho))
    print("%d of %d runs agree with the linear stability bound: %d with spectral radius <= 1 stayed bounded "
          "(%d of them drifted past 1%% of the length scale), %d with radius > 1 diverged"
          % (agree, len(rows), stable_bounded, drifted, unstable_diverged))
    for r, rho in disagreements:
        error = r["max_constraint_error"]
        print("disagrees: %s at h = %s, alpha = %s, beta = %s: radius %.6g, %s (largest violation %s)"
              % (r["/simulation/integrator"], r["/simulation/step"], r["/stabilization/alpha"],
                 r["/stabilization/beta"], rho, r["status"].split(":")[0], error))


if __name__ == "__main__":
    main()
