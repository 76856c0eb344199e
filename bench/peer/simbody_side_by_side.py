#!/usr/bin/env python3
"""tether, MuJoCo and Simbody side by side: runs build/bench/tether_vs_simbody (bench/peer/simbody_bench.cc), saves
its JSON report as bench/peer/results_simbody.json and prints the README's table (markdown): per scene and engine,
the time per simulated second, the error of the bodies' centres at the end against the reference and the largest
constraint violation; then, per scene, each engine's fastest run within 1e-6 m of the reference. Standard library
only.

    python3 bench/peer/simbody_side_by_side.py                                         # run (about 8 minutes)
    python3 bench/peer/simbody_side_by_side.py --json bench/peer/results_simbody.json  # print the saved run again
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import bench_json  # noqa: E402  (bench/bench_json.py)

BINARY = os.path.join(os.path.dirname(os.path.dirname(HERE)), "build", "bench", "tether_vs_simbody")
SCENES = {"double_pendulum": "double pendulum (2 rods), 5 s", "hinge_chain10": "3D hinge chain, 10 rods, 5 s",
          "hinge_chain200": "3D hinge chain, 200 rods, 1 s", "humanoid": "humanoid-sized tree, 5 s",
          "rssr": "RSSR loop, 3 s", "four_bar10": "N-four-bar, N = 10 (21 bars), 5 s"}
MODELS = {
    "tether": {"hinge_chain": "maximal coordinates, 5 rows a hinge", "humanoid": "maximal coordinates, 51 rows",
               "rssr": "maximal coordinates, 2 hinges + 2 ball joints (16 rows)",
               "four_bar": "planar bodies, 31 pins (62 rows)"},
    "mujoco": {"hinge_chain": "hinge joints", "humanoid": "hinge joints",
               "rssr": "hinges + ball joint, 1 connect equality (soft)",
               "four_bar": "hinge joints, 10 connect equalities (soft)"},
    "simbody": {"hinge_chain": "Pin mobilizers", "humanoid": "Pin, Universal, Ball and Weld mobilizers",
                "rssr": "Pin and Ball mobilizers + Constraint::Ball",
                "four_bar": "Pin mobilizers + 10 Constraint::PointOnLine"},
}
ENGINES = {"tether": "tether", "mujoco": "MuJoCo", "simbody": "Simbody"}
REFERENCE = "simbody/rkm_1e-12"  # the reference of every scene but the four-bar (its exact motion)
WITHIN = 1e-6  # m: the accuracy at which the verdict compares the engines' times


def method_label(engine, method):
    if method == "rk4" or method.startswith("rk4_h"):  # rk4 (h = 1 ms) or rk4_hH
        step = "1 ms" if method == "rk4" else f"{float(method[len('rk4_h'):]) * 1e3:g} ms"
        return f"rk4, h = {step}, Baumgarte (100, 2500)" if engine == "tether" else f"RK4, h = {step}"
    name, accuracy = method.split("_")
    accuracy = f"{float(accuracy):.0e}".replace("e-0", "e-")
    return {"rk45": f"rk45 + projection, tolerance {accuracy}",
            "rkm": f"Runge-Kutta-Merson, accuracy {accuracy}",
            "cpodes": f"CPodes (BDF), accuracy {accuracy}"}[name]


def model_label(scene, engine):
    kind = ("hinge_chain" if scene.startswith(("hinge_chain", "double_pendulum"))
            else "four_bar" if scene.startswith("four_bar") else scene)
    return MODELS[engine][kind]


def runs(report):
    """[(scene, engine, method, entry)] in the order the benchmark ran them; entry is the median of the repetitions,
    or the first error when the run failed."""
    medians = {entry["run_name"]: entry for entry in bench_json.measurements(report)}
    out, seen = [], set()
    for entry in report["benchmarks"]:
        name = entry.get("run_name", entry["name"]).split("/iterations")[0]
        if name in seen:
            continue
        seen.add(name)
        scene, engine, method = name.split("/")[:3]
        median = next((m for n, m in medians.items() if n.split("/iterations")[0] == name), None)
        out.append((scene, engine, method, median if median is not None else entry))
    return out


def per_simulated_second(entry):
    """Milliseconds per simulated second."""
    return bench_json.MILLISECONDS[entry.get("time_unit", "ns")] * entry["real_time"] / entry["duration_s"]


def duration(milliseconds):
    if milliseconds >= 1e3:
        return f"{milliseconds / 1e3:.3g} s"
    return f"{milliseconds:.3g} ms" if milliseconds >= 1 else f"{milliseconds * 1e3:.3g} us"


def markdown(table):
    lines = ["| scene | engine | model | integrator | time per simulated second | error at the end | "
             "largest violation | steps |", "|---|---|---|---|---|---|---|---|"]
    for scene, engine, method, entry in table:
        row = f"| {SCENES[scene]} | {ENGINES[engine]} | {model_label(scene, engine)} | {method_label(engine, method)} "
        if entry.get("error_occurred"):
            message = entry.get("error_message", "").strip()
            stall = re.search(r"Unable to advance time past ([0-9]+\.?[0-9]*)", message)
            reason = f"could not advance past t = {float(stall.group(1)):.3g} s" if stall else message.splitlines()[-1]
            lines.append(row + f"| failed: {reason} | | | |")
            continue
        reference = f"{engine}/{method}" == REFERENCE and not scene.startswith("four_bar")
        error = "(the reference)" if reference else f"{entry['error_m']:.1e} m"
        steps = f"{entry['steps']:.0f}" if entry.get("steps") else ""
        lines.append(row + f"| {duration(per_simulated_second(entry))} | {error} | {entry['max_violation_m']:.1e} m "
                     f"| {steps} |")
    return "\n".join(lines)


def verdict(table):
    """Per scene, each engine's fastest run within WITHIN of the reference (the reference itself left out)."""
    lines = []
    for scene in SCENES:
        best = {}
        for s, engine, method, entry in table:
            if s != scene or entry.get("error_occurred") or f"{engine}/{method}" == REFERENCE:
                continue
            if entry["error_m"] <= WITHIN and (engine not in best or per_simulated_second(entry) <
                                               per_simulated_second(best[engine][1])):
                best[engine] = (method, entry)
        parts = []
        for engine in ENGINES:
            if engine in best:
                method, entry = best[engine]
                parts.append(f"{ENGINES[engine]} {duration(per_simulated_second(entry))} "
                             f"({method_label(engine, method)}, {entry['error_m']:.1e} m)")
            else:
                parts.append(f"{ENGINES[engine]} none")
        lines.append(f"{SCENES[scene]}, fastest within {WITHIN:g} m: " + "; ".join(parts))
    return "\n".join(lines)


def main(argv):
    report = bench_json.peer_report(argv, __doc__.splitlines()[0], BINARY, "tether_vs_simbody",
                                    os.path.join(HERE, "results_simbody.json"), interleave=False)  # runs of 0.1 ms up
    table = runs(report)
    print(markdown(table))
    print()
    print(verdict(table))
    print("\nhost: " + bench_json.host(report))


if __name__ == "__main__":
    main(sys.argv[1:])
