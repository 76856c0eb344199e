"""Balances the cart-pole (scenes/cart_pole.json) upright from a 0.2 rad tilt for 10 s with an LQR controller
written in Python, stepping tether's run at 100 Hz (docs/stepping.md).

    /usr/bin/python3 docs/examples/servo/cart_pole_lqr.py     # with build/python on PYTHONPATH

The gains come from the cart-pole's equations linearized about the upright pole (cart M = 1 kg, pole m = 0.5 kg
of length 1 m, its centre lc = 0.5 m from the pivot, I its moment about the centre):
    [[M + m, m lc], [m lc, I + m lc^2]] [x'', th''] = [F, m g lc th]
discretized at the step h = 10 ms (x_{k+1} = (1 + A h) x_k + B h F_k) and solved by iterating the discrete
Riccati equation with Q = diag(1, 10, 1, 1), R = 0.1. The force is held over each step (set_control).
"""
import os

import numpy as np
import tether

HERE = os.path.dirname(os.path.abspath(__file__))
M, m, lc, g, h = 1.0, 0.5, 0.5, 9.81, 0.01
I = m * 1.0**2 / 12

# the scene: the pole upright, tilted 0.2 rad towards +x (a turn of 0.2 about the hinge's y axis), the rail's
# force a control held at 0
scene = tether.Scene.load(os.path.join(HERE, "..", "..", "..", "scenes", "cart_pole.json")).to_dict()
tilt = 0.2
turn = -(np.pi / 2 - tilt)  # about y: the pole's x axis (pivot to tip) from +x to (sin tilt, 0, cos tilt)
scene["bodies"][1]["orientation"] = [np.cos(turn / 2), 0.0, np.sin(turn / 2), 0.0]
scene["bodies"][1]["position"] = [lc * np.sin(tilt), 0.0, lc * np.cos(tilt)]
scene["constraints"][1]["angle"] = tilt  # the hinge's coordinate: the tilt from upright
scene["effects"][1] = {"type": "joint_torque", "joint": "rail", "value": 0.0}
scene["simulation"]["duration"] = 10.0
sim = tether.Scene.from_dict(scene, "cart_pole_upright").stepper()

# LQR on the linearization
mass = np.array([[M + m, m * lc], [m * lc, I + m * lc**2]])
inverse = np.linalg.inv(mass)
A = np.zeros((4, 4))
A[0:2, 2:4] = np.eye(2)
A[2:4, 1] = inverse @ np.array([0.0, m * g * lc])
B = np.zeros((4, 1))
B[2:4, 0] = inverse @ np.array([1.0, 0.0])
Ad, Bd = np.eye(4) + A * h, B * h
Q, R = np.diag([1.0, 10.0, 1.0, 1.0]), np.array([[0.1]])
P = Q.copy()
for _ in range(5000):
    K = np.linalg.solve(R + Bd.T @ P @ Bd, Bd.T @ P @ Ad)
    P = Q + Ad.T @ P @ (Ad - Bd @ K)

while sim.t < 10.0 - h / 2:
    state = np.array([sim["rail.displacement"], sim["pivot.angle"], sim["rail.speed"], sim["pivot.omega"]])
    sim.set_control("rail", float(-(K @ state)[0]))
    sim.step()
run = sim.trajectory()
print("largest tilt after 2 s: %.2e rad; at 10 s: tilt %.2e rad, cart at %.2e m" %
      (np.abs(run["pivot.angle"][run.t >= 2.0]).max(), run["pivot.angle"][-1], run["rail.displacement"][-1]))
