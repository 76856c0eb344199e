"""Scene.simulate: the arrays are the command line's CSV to the last digit; q and v in the model's layouts;
columns(), to_pandas(); the overrides; errors."""
import numpy as np
import pytest

import tether
from conftest import cli, read_csv, source


@pytest.mark.parametrize("scene_file", ["pendulum.json", "four_bar.json", "robot_arm.json"])
def test_arrays_are_the_cli_csv_to_the_last_digit(tmp_path, scene_file):
    path = source("scenes", scene_file)
    cli("simulate", path, "--duration", "0.2", "--every", "10", "-o", tmp_path / "run.csv")
    header, rows = read_csv(tmp_path / "run.csv")
    run = tether.Scene.load(path).simulate(duration=0.2, every=10)
    assert run.names == header
    assert np.array_equal(run.table, np.array(rows))  # exactly: the CSV prints shortest round-trip numbers
    assert np.array_equal(run.t, np.array(rows)[:, 0])
    assert len(run) == len(rows)


def test_q_and_v_are_the_models_layouts():
    run = tether.Scene.load(source("scenes", "robot_arm.json")).simulate(duration=0.05)
    assert run.q.shape == (len(run), 7 * 7)  # seven 3D bodies: position and quaternion
    assert run.v.shape == (len(run), 7 * 6)
    assert np.array_equal(run.q[:, 0], run["link1.x"])
    assert not run.q.flags.owndata  # the run's memory, not a copy
    norms = np.linalg.norm(run.q[:, 3:7], axis=1)
    assert np.allclose(norms, 1.0, atol=1e-12)


def test_columns_and_pandas(pendulum):
    run = tether.Scene.load(pendulum).simulate(duration=0.01)
    columns = run.columns()
    assert list(columns) == run.names
    assert np.array_equal(columns["bob.x"], run["bob.x"])
    assert np.array_equal(run.energy, columns["energy"])
    frame = run.to_pandas()
    assert list(frame.columns) == run.names
    assert np.array_equal(frame["bob.y"].to_numpy(), run["bob.y"])
    with pytest.raises(KeyError, match="no column 'bob.z'"):
        run["bob.z"]


def test_overrides_and_their_errors(pendulum):
    scene = tether.Scene.load(pendulum)
    run = scene.simulate(duration=0.1, step=0.01, integrator="symplectic_euler")
    assert len(run) == 11 and run.t[-1] == 0.1
    with pytest.raises(tether.InputError, match=r"integrator: unknown integrator 'rk9'"):
        scene.simulate(duration=0.1, integrator="rk9")
    with pytest.raises(tether.InputError, match=r"step: must be > 0, got -1"):
        scene.simulate(step=-1.0)
    with pytest.raises(tether.InputError, match=r"duration/step: .* steps"):
        scene.simulate(duration=1e6, step=1e-6)
    with pytest.raises(tether.InputError, match=r"alpha/beta: gains apply to the baumgarte method only"):
        scene.simulate(alpha=1.0, stabilization="projection")
    with pytest.raises(tether.InputError, match=r"solver: unknown"):
        scene.simulate(solver="fastest")
    with pytest.raises(tether.InputError, match=r"rows of 11 numbers, more than the 4 GiB a recording may hold"):
        scene.simulate(duration=1e5, step=1e-4)  # 1e9 steps: refused before it runs
    with pytest.raises(tether.InputError, match=r"every: must be a whole number from 1 to"):
        scene.simulate(every=0)


@pytest.mark.parametrize("settings", [
    {"alpha": 20.0, "step": 2e-3}, {"beta": 50.0, "integrator": "symplectic_euler"},
    {"stabilization": "projection", "solver": "dense"}, {"stabilization": "none", "duration": 0.3}])
def test_settings_as_the_cli_flags(tmp_path, settings):
    path = source("scenes", "four_bar.json")
    flags = sum(([f"--{name}", str(value)] for name, value in settings.items()), [])
    cli("simulate", path, *flags, "--every", "20", "-o", tmp_path / "run.csv")
    _, rows = read_csv(tmp_path / "run.csv")
    assert np.array_equal(tether.Scene.load(path).simulate(every=20, **settings).table, np.array(rows))


def test_a_diverging_run_raises_simulation_diverged():
    scene = tether.Scene.load(source("scenes", "chain20.json"))
    with pytest.raises(tether.SimulationDiverged, match=r"diverged at t = .* constraint"):
        scene.simulate(step=0.01, duration=2.0)


def test_events_are_the_cli_events_file(tmp_path):
    """A rod swinging into a stop at the vertical: trajectory.events is `tether simulate --events`'s table."""
    import csv
    import json
    import math
    a = -math.pi / 2 + math.pi / 3
    scene = {"dimension": 2,
             "bodies": [{"name": "rod", "type": "rigid", "mass": 1.0, "inertia": 1 / 12,
                         "position": [0.5 * math.cos(a), 0.5 * math.sin(a)], "angle": a}],
             "constraints": [{"type": "pin", "name": "hinge", "bodies": ["world", "rod"],
                              "points": [[0.0, 0.0], [-0.5, 0.0]], "angle": math.pi / 3, "range": [0.0, None],
                              "restitution": 0.5}],
             "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
             "simulation": {"duration": 1.5}}
    path = tmp_path / "stop.json"
    path.write_text(json.dumps(scene))
    cli("simulate", path, "-o", tmp_path / "run.csv", "--events", tmp_path / "events.csv")
    with open(tmp_path / "events.csv", newline="") as f:
        rows = list(csv.reader(f))
    run = tether.Scene.load(str(path)).simulate()
    assert rows[0] == list(tether.Event._fields[:5])  # the file's columns, then where and the impulse
    assert [(float(r[0]), r[1], r[2], float(r[3]), float(r[4])) for r in rows[1:]] == [tuple(e)[:5] for e in run.events]
    assert len(run.events) == 2 and run.events[0].kind == "impact" and run.events[0].constraint == "hinge"
    assert run.events[0].speed_after == pytest.approx(-0.5 * run.events[0].speed_before, rel=1e-9)
    assert list(run.events_to_pandas().columns) == list(tether.Event._fields)


@pytest.mark.parametrize("mode", ["events", "stepping"])
def test_a_ball_bounces_on_a_floor_in_both_contact_modes(mode):
    """A ball (e = 0.8) dropped 1 m on a floor: the first impact at sqrt(2 h / g), exactly when events are located,
    within a step when impulses resolve the step ends; Newton's law at it."""
    import math
    scene = {"dimension": 3,
             "bodies": [{"name": "ball", "type": "particle", "mass": 1.0, "position": [0.0, 0.0, 1.1]}],
             "shapes": [{"name": "surface", "body": "ball", "type": "sphere", "radius": 0.1, "restitution": 0.8},
                        {"name": "floor", "body": "world", "type": "plane"}],
             "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}],
             "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 0.6, "contact": mode}}
    run = tether.Scene.from_dict(scene).simulate()
    impact = run.events[0]
    assert impact.kind == "impact" and impact.constraint == "surface|floor"
    assert impact.t == pytest.approx(math.sqrt(2 / 9.81), abs=1e-12 if mode == "events" else 1e-3)
    assert impact.speed_after == pytest.approx(-0.8 * impact.speed_before, rel=1e-9 if mode == "events" else 1e-4)
    # where: under the ball on the floor, the normal up; the impulse the ball's change of momentum, m (1 + e) v
    assert impact.point == pytest.approx((0.0, 0.0, 0.0), abs=1e-9 if mode == "events" else 5e-3)
    assert impact.normal == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)
    assert impact.impulse == pytest.approx(1.8 * -impact.speed_before, rel=1e-9 if mode == "events" else 1e-4)
