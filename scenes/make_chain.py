#!/usr/bin/env python3
"""Writes a tether scene of a falling chain of N particles to stdout.

    python3 scenes/make_chain.py N [--length L] [--mass M] [--duration T] [--step H]
                                   [--stabilization projection|none|default] > scenes/chainN.json

The chain is N particles p0 .. p{N-1} joined by N distance constraints: constraint 0 holds p0 at one link length
L / N from the world origin, constraint k joins p{k-1} and p{k}. It starts horizontal and at rest, p{k} at
((k + 1) L / N, 0), and falls under gravity (0, -9.81) m/s^2. Defaults: total length L = 2 m, total mass
M = 1 kg (M / N per particle), rk4 with step H = 1e-3 s for T = 2 s.

Stabilization defaults to "projection". A chain released horizontally cracks like a whip: its free end swings
through the bottom at high speed, twice in 2 s for the default chain, and at the second pass (t ~ 1.97 s) the
last links turn at up to ~1500 rad/s. rk4 with h = 1e-3 s does not resolve that and diverges with Baumgarte
gains (the default rule's or others) or with none; projection keeps it on its constraints. "default" writes no
"stabilization" key, so that tether uses its default Baumgarte gain rule (docs/scene-format.md); it suits short
chains, short durations, rk45 or h <= 2.5e-4 s.

scenes/chain100.json is `python3 scenes/make_chain.py 100`. Python 3 standard library only.
"""
import argparse
import json
import sys


def chain(n, length, mass, duration, step, stabilization):
    link = length / n
    bodies, constraints = [], []
    for k in range(n):
        # the position divides last, so that it prints as short as it is (0.06, not 0.06000000000000001)
        bodies.append({"name": f"p{k}", "type": "particle", "mass": mass / n,
                       "position": [(k + 1) * length / n, 0.0]})
        constraints.append({"type": "distance", "bodies": ["world" if k == 0 else f"p{k - 1}", f"p{k}"],
                            "length": link})
    scene = {"dimension": 2,
             "bodies": bodies,
             "constraints": constraints,
             "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
             "simulation": {"integrator": "rk4", "step": step, "duration": duration}}
    if stabilization != "default":
        scene["stabilization"] = {"method": stabilization}
    return scene


def dump(value, indent=0, used=0):
    """JSON with 2-space indentation: each body, constraint and effect on a line of its own, and any object or
    array that fits in a 118-character line kept on one line. `used` counts the characters before the value."""
    flat = json.dumps(value)
    objects = isinstance(value, list) and any(isinstance(v, dict) for v in value)
    if not isinstance(value, (dict, list)) or (indent > 0 and not objects and indent + used + len(flat) <= 118):
        return flat
    if not value:
        return flat
    pad, inner = " " * indent, " " * (indent + 2)
    if isinstance(value, dict):
        items = []
        for k, v in value.items():
            key = json.dumps(k)
            items.append(f"{inner}{key}: {dump(v, indent + 2, len(key) + 2)}")
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    items = [inner + dump(v, indent + 2) for v in value]
    return "[\n" + ",\n".join(items) + "\n" + pad + "]"


def main(argv):
    parser = argparse.ArgumentParser(description="Writes a tether scene of a falling chain of N particles.")
    parser.add_argument("n", type=int, help="number of particles (>= 1)")
    parser.add_argument("--length", type=float, default=2.0, help="total length of the chain, m (default 2)")
    parser.add_argument("--mass", type=float, default=1.0, help="total mass of the chain, kg (default 1)")
    parser.add_argument("--duration", type=float, default=2.0, help="simulated time, s (default 2)")
    parser.add_argument("--step", type=float, default=1e-3, help="time step, s (default 1e-3)")
    parser.add_argument("--stabilization", choices=["projection", "none", "default"],
                        default="projection",
                        help="stabilization method (default projection); 'default' omits the key, which selects "
                             "the default Baumgarte gain rule")
    args = parser.parse_args(argv)
    if args.n < 1:
        parser.error("N must be at least 1")
    for name in ("length", "mass", "duration", "step"):
        if not getattr(args, name) > 0:
            parser.error(f"--{name} must be > 0")
    scene = chain(args.n, args.length, args.mass, args.duration, args.step, args.stabilization)
    sys.stdout.write(dump(scene) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
