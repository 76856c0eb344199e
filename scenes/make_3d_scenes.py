#!/usr/bin/env python3
"""Writes the shipped 3D scenes (and the planar acrobot) with their initial states worked out exactly, so that
none of them needs assembling: python3 scenes/make_3d_scenes.py [OUT_DIR] (default: this folder).

  heavy_top.json     a symmetric top on its tip (a ball joint at the world origin), tilted 30 degrees and spinning
                     at 50 rad/s about its axis: it precesses and nutates under gravity
  tumbling_box.json  a free box spun about its intermediate principal axis with a small perturbation: it flips
                     over every few seconds (the Dzhanibekov effect), no gravity
  robot_arm.json     a 7-joint arm (hinges alternating about z and y, like a KUKA iiwa) hanging from its base, a
                     motor (joint_torque) at every joint driving it for 2 s, gravity, angular damping; named joints
                     give encoder columns, a fingertip marker
  rssr.json          a spatial four-bar: a crank hinged about z (starting at 60 degrees, away from the
                     configuration where crank and rocker move independently) and driven by a motor, a rocker hinged about x, a
                     coupler with ball joints at both ends (its spin about its own line is the linkage's second,
                     idle, degree of freedom), gravity
  cardan.json        a Cardan (universal) joint between an input shaft and an output shaft 30 degrees apart, both
                     on world hinges: three of its rows are redundant
  acrobot.json       the classic acrobot: two 1 m, 1 kg rods in the plane, the shoulder pinned to the world
                     and a motor at the elbow only (41 knots over 5 s), hanging at rest
  cart_pole.json     a 1 kg cart on a rail (a prismatic joint with a motor: a force along it) and a 1 m, 0.5 kg
                     pole hinged to it, hanging at rest (16 knots over 3 s)
Standard library only.
"""
import json
import math
import os
import sys

G = 9.81


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def qaxis(axis, angle):
    u = unit(axis)
    return [math.cos(angle / 2)] + [math.sin(angle / 2) * x for x in u]


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return [w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2]


def qrot(q, r):
    w, v = q[0], q[1:]
    t = [2 * (v[1] * r[2] - v[2] * r[1]), 2 * (v[2] * r[0] - v[0] * r[2]), 2 * (v[0] * r[1] - v[1] * r[0])]
    c = [v[1] * t[2] - v[2] * t[1], v[2] * t[0] - v[0] * t[2], v[0] * t[1] - v[1] * t[0]]
    return [r[k] + w * t[k] + c[k] for k in range(3)]


def rod(mass, length, radius=0.02):
    """Principal moments of a solid rod along body x."""
    transverse = mass * (3 * radius * radius + length * length) / 12
    return [0.5 * mass * radius * radius, transverse, transverse]


def rigid(name, mass, inertia, position, orientation=None, angular_velocity=None):
    body = {"name": name, "type": "rigid", "mass": mass, "inertia": inertia, "position": position}
    if orientation is not None:
        body["orientation"] = orientation
    if angular_velocity is not None:
        body["angular_velocity"] = angular_velocity
    return body


def scene(bodies, constraints=(), effects=(), markers=(), **simulation):
    out = {"dimension": 3, "bodies": list(bodies), "constraints": list(constraints), "effects": list(effects)}
    if markers:
        out["markers"] = list(markers)
    out["simulation"] = {"integrator": "rk4", "step": 1e-3, **simulation}
    return out


def heavy_top():
    tilt = qaxis([1, 0, 0], math.radians(30))
    axis = qrot(tilt, [0, 0, 1])
    arm = 0.1  # tip to centre of mass
    return scene([rigid("top", 1.0, [0.02, 0.02, 0.035], [arm * a for a in axis], tilt, [50 * a for a in axis])],
                 [{"type": "pin", "name": "tip", "bodies": ["world", "top"], "points": [[0, 0, 0], [0, 0, -arm]]}],
                 [{"type": "gravity", "acceleration": [0, 0, -G]}], duration=5.0)


def tumbling_box():
    m, a, b, c = 1.0, 0.3, 0.2, 0.1
    inertia = [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]
    return scene([rigid("box", m, inertia, [0, 0, 0], None, [0.01, 5.0, 0.01])], duration=10.0)


def robot_arm():
    lengths = [0.34, 0.4, 0.4, 0.4, 0.3, 0.2, 0.1]
    masses = [4.0, 4.0, 3.0, 2.7, 1.7, 1.8, 0.3]
    axes = [[0, 0, 1], [0, 1, 0]] * 3 + [[0, 0, 1]]
    hanging = qaxis([0, 1, 0], math.pi / 2)  # body x (each link's length) along world -z
    bodies, joints, effects = [], [], [{"type": "gravity", "acceleration": [0, 0, -G]}]
    z = 0.0
    for k, (length, mass) in enumerate(zip(lengths, masses)):
        bodies.append(rigid(f"link{k + 1}", mass, rod(mass, length, 0.06), [0, 0, z - length / 2], hanging))
        parent = "world" if k == 0 else f"link{k}"
        on_parent = [0, 0, 0] if k == 0 else [lengths[k - 1] / 2, 0, 0]
        # the axis in the parent's frame: the world axis turned into body axes (every link starts hanging)
        axis = axes[k] if k == 0 else qrot([hanging[0]] + [-x for x in hanging[1:]], axes[k])
        joints.append({"type": "hinge", "name": f"a{k + 1}", "bodies": [parent, f"link{k + 1}"],
                       "points": [on_parent, [-length / 2, 0, 0]], "axis": [round(x, 15) + 0.0 for x in axis]})
        z -= length
    torques = [3.0, 20.0, 1.0, -8.0, 0.5, 1.5, 0.1]
    for k, value in enumerate(torques):
        effects.append({"type": "joint_torque", "joint": f"a{k + 1}",
                        "schedule": {"times": [0.0, 1.0, 2.0], "values": [0.0, value, 0.0]}})
    effects.append({"type": "damping", "coefficient": 0.0, "angular_coefficient": 0.02})
    markers = [{"name": "fingertip", "body": "link7", "point": [lengths[-1] / 2, 0, 0]}]
    return scene(bodies, joints, effects, markers, duration=2.0)


def rssr():
    crank, rocker, start = 1.0, 1.5, math.radians(60)
    pivot = [3.0, 0.0, 1.0]
    p = [crank * math.cos(start), crank * math.sin(start), 0.0]  # crank tip
    r = [pivot[0], 0.0, pivot[2] - rocker]     # rocker tip, hanging
    d = [r[k] - p[k] for k in range(3)]
    length = math.sqrt(sum(x * x for x in d))
    # the coupler's body x along d: a turn about z to d's azimuth, then about the new y to its elevation
    along = qmul(qaxis([0, 0, 1], math.atan2(d[1], d[0])), qaxis([0, 1, 0], math.atan2(-d[2], math.hypot(d[0], d[1]))))
    down = qaxis([0, 1, 0], math.pi / 2)       # the rocker's body x down
    bodies = [rigid("crank", 1.0, rod(1.0, crank), [x / 2 for x in p], qaxis([0, 0, 1], start)),
              rigid("coupler", 1.0, rod(1.0, length), [(p[k] + r[k]) / 2 for k in range(3)], along),
              rigid("rocker", 1.0, rod(1.0, rocker), [pivot[0], 0.0, pivot[2] - rocker / 2], down)]
    joints = [{"type": "hinge", "name": "drive", "bodies": ["world", "crank"], "points": [[0, 0, 0], [-crank / 2, 0, 0]],
               "axis": [0, 0, 1]},
              {"type": "pin", "bodies": ["crank", "coupler"], "points": [[crank / 2, 0, 0], [-length / 2, 0, 0]]},
              {"type": "pin", "bodies": ["coupler", "rocker"], "points": [[length / 2, 0, 0], [rocker / 2, 0, 0]]},
              {"type": "hinge", "name": "rock", "bodies": ["world", "rocker"], "points": [pivot, [-rocker / 2, 0, 0]],
               "axis": [1, 0, 0]}]
    effects = [{"type": "gravity", "acceleration": [0, 0, -G]}, {"type": "joint_torque", "joint": "drive", "value": 2.0}]
    return scene(bodies, joints, effects, duration=3.0)


def cardan():
    beta = math.radians(30.0)
    b = [math.cos(beta), math.sin(beta), 0.0]
    out_q = qaxis([0, 0, 1], beta)
    bodies = [rigid("input", 1.0, [0.002, 0.01, 0.01], [0, 0, 0], None, [5.0, 0, 0]),
              rigid("output", 0.5, [0.001, 0.005, 0.005], [0, 0, 0], out_q, [5.0 / math.cos(beta) * x for x in b])]
    joints = [{"type": "hinge", "name": "in", "bodies": ["world", "input"], "points": [[0, 0, 0], [0, 0, 0]],
               "axis": [1, 0, 0]},
              {"type": "hinge", "name": "out", "bodies": ["world", "output"], "points": [[0, 0, 0], [0, 0, 0]],
               "axis": b},
              {"type": "universal", "bodies": ["input", "output"], "points": [[0, 0, 0], [0, 0, 0]],
               "axes": [[0, 1, 0], [0, 0, 1]]}]
    effects = [{"type": "joint_torque", "joint": "in", "value": 0.05}]
    return scene(bodies, joints, effects, duration=4.0)


def acrobot():
    times = [0.125 * k for k in range(41)]
    return {"dimension": 2,
            "bodies": [{"name": "upper", "type": "rigid", "mass": 1.0, "inertia": 1.0 / 12, "position": [0.0, -0.5],
                        "angle": -math.pi / 2},
                       {"name": "lower", "type": "rigid", "mass": 1.0, "inertia": 1.0 / 12, "position": [0.0, -1.5],
                        "angle": -math.pi / 2}],
            "constraints": [{"type": "pin", "name": "shoulder", "bodies": ["world", "upper"],
                             "points": [[0.0, 0.0], [-0.5, 0.0]]},
                            {"type": "pin", "name": "elbow", "bodies": ["upper", "lower"],
                             "points": [[0.5, 0.0], [-0.5, 0.0]]}],
            "effects": [{"type": "gravity", "acceleration": [0.0, -G]},
                        {"type": "joint_torque", "joint": "elbow",
                         "schedule": {"times": times, "values": [0.0] * len(times)}}],
            "markers": [{"name": "tip", "body": "lower", "point": [0.5, 0.0]}],
            "simulation": {"integrator": "rk4", "step": 0.01, "duration": 5.0}}


def cart_pole():
    """A 1 kg cart on a rail along x (a prismatic joint with a motor: a force) and a 1 m, 0.5 kg pole hinged to it
    about y, hanging at rest; 16 knots over 3 s."""
    times = [0.2 * k for k in range(16)]
    hanging = qaxis([0, 1, 0], math.pi / 2)  # the pole's body x (its length) along world -z
    bodies = [rigid("cart", 1.0, [0.05, 0.05, 0.05], [0.0, 0.0, 0.0]),
              rigid("pole", 0.5, rod(0.5, 1.0), [0.0, 0.0, -0.5], hanging)]
    joints = [{"type": "prismatic", "name": "rail", "bodies": ["world", "cart"], "points": [[0, 0, 0], [0, 0, 0]],
               "axis": [1, 0, 0]},
              {"type": "hinge", "name": "pivot", "bodies": ["cart", "pole"], "points": [[0, 0, 0], [-0.5, 0, 0]],
               "axis": [0, 1, 0]}]
    effects = [{"type": "gravity", "acceleration": [0, 0, -G]},
               {"type": "joint_torque", "joint": "rail", "schedule": {"times": times, "values": [0.0] * len(times)}}]
    markers = [{"name": "tip", "body": "pole", "point": [0.5, 0, 0]}]
    return scene(bodies, joints, effects, markers, step=0.01, duration=3.0)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    for name, build in (("heavy_top", heavy_top), ("tumbling_box", tumbling_box), ("robot_arm", robot_arm),
                        ("rssr", rssr), ("cardan", cardan), ("acrobot", acrobot), ("cart_pole", cart_pole)):
        with open(os.path.join(out, name + ".json"), "w") as f:
            json.dump(build(), f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
