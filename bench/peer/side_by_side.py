#!/usr/bin/env python3
"""tether against MuJoCo, side by side: runs build/bench/tether_vs_mujoco (bench/peer/peer_bench.cc), saves its
JSON report as bench/peer/results.json and prints the README's table (markdown) with the ratio per scene, then
the two figures issue 8 asks for. Standard library only.

    python3 bench/peer/side_by_side.py                                   # run (about 45 minutes), then print
    python3 bench/peer/side_by_side.py --json bench/peer/results.json    # print the saved run again
    python3 bench/peer/side_by_side.py --filter 'hinge_chain|humanoid' --out bench/peer/results_rigid3d.json
                                                                         # the rigid-body scenes only (5 minutes)
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import bench_json  # noqa: E402  (bench/bench_json.py)

BINARY = os.path.join(os.path.dirname(os.path.dirname(HERE)), "build", "bench", "tether_vs_mujoco")
MUJOCO_MODELS = {"mujoco_slides": "slide joints + tendon equalities", "mujoco_free": "free bodies + connect",
                 "mujoco": "hinges + connect"}
REDUCED = "hinge joints (reduced coordinates)"  # the MuJoCo model of the rigid-body scenes


def mujoco_model(scene, engine):
    return MUJOCO_MODELS[engine] if scene == "four_bar" or engine != "mujoco" else REDUCED
INTEGRATORS = {"euler": ("symplectic Euler", "Euler"), "rk4": ("rk4", "RK4")}


def microseconds_per_step(entry):
    return 1e6 / entry["items_per_second"]


def runs(report):
    """{(scene, integrator, engine): entry} from the medians of the report."""
    table = {}
    for entry in bench_json.measurements(report):
        scene, integrator, engine = entry["run_name"].split("/")[:3]
        table[(scene, integrator, engine)] = entry
    return table


def scene_label(scene):
    if scene == "four_bar":
        return "four-bar"
    if scene == "humanoid":
        return "humanoid-sized tree (13 bodies, 21 hinges)"
    if scene == "humanoid_file":
        return "MuJoCo's humanoid.xml (imported, torso fixed)"
    for prefix, unit in (("hinge_chain", "3D hinge chain, {} rods"), ("chain", "chain, {} particles")):
        if scene.startswith(prefix) and scene[len(prefix):].isdigit():
            return unit.format(scene[len(prefix):])
    sys.exit(f"side_by_side.py: no label for the scene '{scene}' (bench/peer/peer_bench.cc's names)")


def rows(table):
    """One row per scene, integrator and MuJoCo model, in the order the benchmark ran them."""
    out = []
    for (scene, integrator, engine), mujoco in table.items():
        if engine not in MUJOCO_MODELS:
            continue
        tether = table.get((scene, integrator, "tether"))
        if tether is None:
            continue
        out.append((scene, integrator, engine, tether, mujoco))
    return out


def per_step(microseconds):
    return f"{microseconds / 1e3:.3g} ms" if microseconds >= 1e3 else f"{microseconds:.3g} us"


def percent(fraction):
    return f"{100 * fraction:.2g}%"


def energy_error(entry):
    """The energy error as a fraction of the potential drop, or 'damped' where the scene's effects take energy out
    (humanoid.xml's joint damping: the error then measures no integrator)."""
    return percent(entry["energy_error_of_drop"]) if entry.get("conservative", 1) else "damped"


def markdown(table):
    lines = ["| scene | integrator (tether / MuJoCo) | MuJoCo model | tether, per step | MuJoCo, per step | "
             "MuJoCo / tether | violation, tether | violation, MuJoCo | energy error, tether | energy error, MuJoCo |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for scene, integrator, engine, tether, mujoco in rows(table):
        ours, theirs = microseconds_per_step(tether), microseconds_per_step(mujoco)
        lines.append(
            f"| {scene_label(scene)} | {' / '.join(INTEGRATORS[integrator])} | {mujoco_model(scene, engine)} "
            f"| {per_step(ours)} | {per_step(theirs)} | {theirs / ours:.1f} "
            f"| {tether['max_violation_m']:.1e} m | {mujoco['max_violation_m']:.1e} m "
            f"| {energy_error(tether)} | {energy_error(mujoco)} |")
    for integrator in INTEGRATORS:
        projection = table.get(("four_bar", integrator, "tether_projection"))
        if projection:
            lines.append(f"\nfour-bar, {INTEGRATORS[integrator][0]}, tether with projection instead of Baumgarte: "
                         f"{per_step(microseconds_per_step(projection))} per step, violation "
                         f"{projection['max_violation_m']:.1e} m, energy error "
                         f"{percent(projection['energy_error_of_drop'])}")
    return "\n".join(lines)


def rk4_goal(table, scene, label, at_most, digits=2, violation=False):
    """One verdict line: tether's rk4 step on `scene` as a fraction of MuJoCo's against the goal `at_most` (and its
    violation against 1e-6 m), or None where the run has not both."""
    ours, theirs = table.get((scene, "rk4", "tether")), table.get((scene, "rk4", "mujoco"))
    if not (ours and theirs):
        return None
    ratio = microseconds_per_step(ours) / microseconds_per_step(theirs)
    asked = "no slower asked" if at_most == 1.0 else f"at most {at_most:g} asked"
    line = (f"{label}, rk4: tether takes {ratio:.{digits}f} of MuJoCo's time per step ({asked}: "
            f"{'yes' if ratio <= at_most else 'NO'})")
    if violation:
        line += (f", violation {ours['max_violation_m']:.2e} m (below 1e-6 m asked: "
                 f"{'yes' if ours['max_violation_m'] < 1e-6 else 'NO'})")
    return line


def verdict(table):
    """Issue 8's two figures (the 200-particle rk4 chain and the four-bar), issue 14's (the 200-rod rk4 hinge chain
    and the humanoid-sized tree) and issue 38's (humanoid.xml and the 10-rod hinge chain)."""
    goals = [rk4_goal(table, "hinge_chain200", "3D hinge chain of 200 rods", 0.2, digits=3, violation=True),
             rk4_goal(table, "humanoid", "humanoid-sized tree", 1.0),
             rk4_goal(table, "humanoid_file", "MuJoCo's humanoid.xml", 0.5, violation=True),
             rk4_goal(table, "hinge_chain10", "3D hinge chain of 10 rods", 1.0)]
    lines = [line for line in goals if line]
    tether = table.get(("chain200", "rk4", "tether"))
    for engine in ("mujoco_slides", "mujoco_free"):
        mujoco = table.get(("chain200", "rk4", engine))
        if tether and mujoco:
            ratio = microseconds_per_step(tether) / microseconds_per_step(mujoco)
            lines.append(f"chain of 200, rk4, against MuJoCo's {MUJOCO_MODELS[engine]}: tether takes {ratio:.3f} of "
                         f"MuJoCo's time per step (at most 0.2 asked: {'yes' if ratio <= 0.2 else 'NO'}), violation "
                         f"{tether['max_violation_m']:.2e} m (below 1e-6 m asked: "
                         f"{'yes' if tether['max_violation_m'] < 1e-6 else 'NO'})")
    for integrator in INTEGRATORS:
        ours, theirs = table.get(("four_bar", integrator, "tether")), table.get(("four_bar", integrator, "mujoco"))
        if ours and theirs:
            ratio = microseconds_per_step(ours) / microseconds_per_step(theirs)
            lines.append(f"four-bar, {INTEGRATORS[integrator][0]}: tether takes {ratio:.2f} of MuJoCo's time per step "
                         f"(no slower asked: {'yes' if ratio <= 1.0 else 'NO'})")
    return "\n".join(lines)


def main(argv):
    report = bench_json.peer_report(argv, __doc__.splitlines()[0], BINARY, "tether_vs_mujoco", os.path.join(HERE, "results.json"))
    table = runs(report)
    print(markdown(table))
    print()
    print(verdict(table))
    print("\nhost: " + bench_json.host(report))


if __name__ == "__main__":
    main(sys.argv[1:])
