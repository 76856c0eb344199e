"""Scene.stepper (docs/stepping.md): a run stepped from Python is simulate's bit for bit when no control is set;
controls, states, the recording's branches, errors, the lock released while it steps; the servo examples
(docs/examples/servo/) reach their pose, recover their gains to 1% and balance the cart-pole."""
import json
import os
import re
import subprocess
import sys
import threading

import numpy as np
import pytest
import tether
from conftest import cli, source


def load(*path):
    return tether.Scene.load(source(*path))


def same_run(a, b):
    assert a.names == b.names
    assert np.array_equal(a.table, b.table, equal_nan=True)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.v, b.v)
    assert a.events == b.events


@pytest.mark.parametrize("path, every", [(("scenes", "cart_pole.json"), 1), (("scenes", "cart_pole.json"), 7),
                                         (("scenes", "robot_arm.json"), 1),
                                         (("docs", "examples", "contact", "bounce_and_slide.json"), 3),
                                         (("docs", "examples", "limits", "stop.json"), 1)])
def test_a_run_stepped_from_python_is_simulates_bit_for_bit(path, every):
    scene = load(*path)
    reference = scene.simulate(every=every)
    sim = scene.stepper(every=every)
    steps = int(round(sim.end / scene.to_dict()["simulation"].get("step", 1e-3)))
    sim.step(steps // 3)
    sim.step_to(sim.end / 2)
    while sim.t < sim.end:
        sim.step()
    same_run(sim.trajectory(), reference)
    assert sim.q.tolist() == reference.q[-1].tolist() and sim.v.tolist() == reference.v[-1].tolist()
    for name in ("t", "energy"):
        assert sim[name] == reference[name][-1]


def test_a_control_held_from_the_start_is_the_scene_with_that_value():
    document = load("scenes", "cart_pole.json").to_dict()
    sim = tether.Scene.from_dict(document).stepper()
    assert sim.control("rail") == 0.0 and sim.control("/effects/1") == 0.0
    sim.set_control("rail", 1.5)
    sim.step_to(sim.end)
    document["effects"][1] = {"type": "joint_torque", "joint": "rail", "value": 1.5}
    same_run(sim.trajectory(), tether.Scene.from_dict(document).simulate())


def test_a_servo_target_is_a_control_and_a_joint_with_two_controls_is_named_by_pointer():
    document = load("docs", "examples", "servo", "arm.json").to_dict()
    document["effects"].append({"type": "joint_torque", "joint": "elbow", "value": 0.0})
    sim = tether.Scene.from_dict(document, "arm").stepper()
    assert sim.control("shoulder") == 0.0
    with pytest.raises(tether.InputError, match=r"'elbow' names several controls \(/effects/2 \(the joint_servo on "
                                                r"'elbow'\), /effects/3 \(the joint_torque on 'elbow'\)\)"):
        sim.set_control("elbow", 1.0)
    sim.set_control("/effects/2", -0.5).set_control("shoulder", 0.5)
    sim.step_to(3.0)
    assert abs(sim["shoulder.angle"] - 0.5) < 1e-6 and abs(sim["elbow.angle"] + 0.5) < 1e-6


def test_states_put_back_the_run_and_cut_the_recording_back_to_them():
    scene = load("scenes", "cart_pole.json")
    reference = scene.simulate()
    sim = scene.stepper()
    sim.step(50)
    start = sim.state()
    sim.set_control("rail", 3.0).step(100)
    pushed = sim.state()
    pushed_q = sim.q
    sim.set_state(start)  # on the recording's path: cut back to t = 0.5 s, the schedule's control again
    assert sim.t == 0.5 and len(sim.trajectory()) == 51 and sim.control("rail") == 0.0
    sim.step_to(sim.end)
    same_run(sim.trajectory(), reference)
    sim.set_state(pushed)  # a rollout since abandoned: the recording starts again at its state
    assert sim.t == 1.5 and sim.control("rail") == 3.0 and sim.q.tolist() == pushed_q.tolist()
    run = sim.trajectory()
    assert len(run) == 1 and run.t[0] == 1.5
    other = scene.stepper()
    with pytest.raises(tether.InputError, match="saved by another stepper"):
        other.set_state(start)


def test_bad_requests_are_refused_and_leave_the_run_as_it_was():
    sim = load("scenes", "cart_pole.json").stepper(duration=0.05)
    sim.step(2)
    q = sim.q
    with pytest.raises(tether.InputError, match=r"4 steps would pass the run's end at t = 0.05 s \(3 are left\)"):
        sim.step(4)
    with pytest.raises(tether.InputError, match="past the run's end"):
        sim.step_to(1.0)
    assert sim.t == 0.02 and sim.q.tolist() == q.tolist()
    with pytest.raises(tether.InputError, match="no control 'pivot'.*/effects/1 \\(the joint_torque on 'rail'\\)"):
        sim.set_control("pivot", 1.0)
    with pytest.raises(tether.InputError, match="expected a finite number"):
        sim.set_control("rail", float("nan"))
    with pytest.raises(KeyError, match="no column 'pole.angle'"):
        sim["pole.angle"]
    with pytest.raises(tether.InputError, match="n: must be"):
        sim.step(-1)
    assert "pivot.angle" in sim.columns()
    sim.step(3)
    assert sim.t == pytest.approx(0.05) and len(sim.trajectory()) == 6


def test_a_run_that_diverges_says_so_and_goes_on_from_a_saved_state():
    document = load("scenes", "pendulum.json").to_dict()
    document["simulation"] = {"integrator": "euler", "step": 0.05, "duration": 100.0}
    document["stabilization"] = {"method": "none"}
    sim = tether.Scene.from_dict(document, "explodes").stepper()
    start = sim.state()
    with pytest.raises(tether.SimulationDiverged, match="explodes"):
        sim.step(1999)
    with pytest.raises(tether.InputError, match="the run stopped"):
        sim.step()
    sim.set_state(start)
    sim.step(1)
    assert sim.t == 0.05


def test_the_interpreters_lock_is_released_while_it_steps():
    sim = load("scenes", "chain100.json").stepper()
    counted = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counted.append(1)
    thread = threading.Thread(target=count)
    thread.start()
    try:
        sim.step(200)
    finally:
        stop.set()
        thread.join()
    assert len(counted) > 1000
    # another thread's calls while it steps are refused, not raced
    sim = load("scenes", "cart_pole.json").stepper(duration=2000.0)
    stepping = threading.Thread(target=lambda: sim.step(200000))
    stepping.start()
    refused = 0
    while stepping.is_alive():
        try:
            sim.set_control("rail", 0.0)
        except tether.InputError as error:
            assert "is stepping in another thread" in str(error)
            refused += 1
    stepping.join()
    assert refused > 0 and sim.t == pytest.approx(2000.0)


def test_the_servo_arm_reaches_its_pose_and_its_gains_are_identified_to_one_percent():
    sim = tether.Scene.load(source("docs", "examples", "servo", "arm.json")).stepper()
    sim.step_to(sim.end)
    assert abs(sim["shoulder.angle"] - 1.0) < 1e-6 and abs(sim["elbow.angle"] + 1.5) < 1e-6
    result = json.loads(cli("identify", source("docs", "examples", "servo", "guess.json"), "--data",
                            source("docs", "examples", "servo", "joint_angles.csv"), "--param", "/effects/1/kp",
                            "--param", "/effects/1/kd", "--param", "/effects/2/kp", "--param", "/effects/2/kd"))
    truth = {"/effects/1/kp": 40.0, "/effects/1/kd": 6.0, "/effects/2/kp": 20.0, "/effects/2/kd": 2.0}
    assert not result["failed"]
    for pointer, value in truth.items():
        assert abs(result["parameters"][pointer] / value - 1.0) < 0.01, pointer


def test_the_lqr_example_balances_the_cart_pole_for_10_s():
    package = os.path.dirname(os.path.dirname(os.path.abspath(tether.__file__)))
    done = subprocess.run([sys.executable, source("docs", "examples", "servo", "cart_pole_lqr.py")],
                          capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=package))
    assert done.returncode == 0, done.stderr
    largest, last_tilt, cart = map(float, re.findall(r"-?\d\.\d+e[-+]\d+", done.stdout))
    assert largest < 0.02 and abs(last_tilt) < 1e-4 and abs(cart) < 1e-3, done.stdout


def test_a_recording_too_large_is_refused_up_front():
    scene = load("scenes", "chain100.json")
    with pytest.raises(tether.InputError, match="more than the 4 GiB a recording may hold"):
        scene.stepper(duration=1e5)
    sim = scene.stepper(duration=1e5, every=100000).step(2)  # fewer rows fit: the first, then every 100000th step
    assert len(sim.trajectory()) == 1 and sim.t == pytest.approx(0.002)
