"""tether.gradient: what `tether gradient` prints, against central differences, with data as a dict, a
DataFrame or a Trajectory."""
import numpy as np
import pandas
import pytest

import tether
from conftest import cli_json, source

PARAMS = ["/bodies/0/mass", "/effects/0/acceleration/1", "/bodies/0/velocity/0"]


@pytest.fixture
def observed(tmp_path, pendulum):
    """The pendulum's own run at five times, shifted so that the loss is not zero, as a dict and as a file."""
    run = tether.Scene.load(pendulum).simulate(duration=0.5, every=100)
    data = {"t": run.t[1:], "bob.x": run["bob.x"][1:] + 0.01, "bob.vy": run["bob.vy"][1:] - 0.02}
    path = tmp_path / "observed.csv"
    with open(path, "w") as f:
        f.write("t,bob.x,bob.vy\n")
        for row in zip(*data.values()):
            f.write(",".join(repr(float(x)) for x in row) + "\n")
    return data, path


def scene_with_velocity(pendulum):
    scene = tether.Scene.load(pendulum).set("/simulation/duration", 0.5)
    return scene.set("/bodies/0/velocity/0", 0.3)


def test_as_the_cli_prints_it(tmp_path, pendulum, observed):
    data, path = observed
    scene = scene_with_velocity(pendulum)
    scene_path = tmp_path / "scene.json"
    scene_path.write_text(__import__("json").dumps(scene.to_dict()))
    expected = cli_json("gradient", scene_path, "--data", path, *sum((["--param", p] for p in PARAMS), []))
    got = tether.gradient(scene, data, PARAMS)
    assert got["loss"] == expected["loss"]
    assert got["gradient"] == expected["gradient"]
    assert got["parameters"] == expected["parameters"]
    assert got["method"] == "jet" and got["seconds"] > 0


def test_against_central_differences(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    got = tether.gradient(scene, data, PARAMS)
    for pointer in PARAMS:
        value = got["parameters"][pointer]
        h = 1e-6 * max(abs(value), 1.0)
        plus = tether.gradient(tether.Scene.from_dict(scene.to_dict()).set(pointer, value + h), data, PARAMS)["loss"]
        minus = tether.gradient(tether.Scene.from_dict(scene.to_dict()).set(pointer, value - h), data, PARAMS)["loss"]
        assert got["gradient"][pointer] == pytest.approx((plus - minus) / (2 * h), rel=1e-6, abs=1e-9)
    fd = tether.gradient(scene, data, PARAMS, method="fd")
    for pointer in PARAMS:
        assert fd["gradient"][pointer] == pytest.approx(got["gradient"][pointer], rel=1e-5, abs=1e-8)


def test_the_adjoint_gives_the_jets_gradient_and_what_it_kept(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    jet = tether.gradient(scene, data, PARAMS, method="jet")
    adjoint = tether.gradient(scene, data, PARAMS, method="adjoint")
    assert adjoint["method"] == "adjoint" and "adjoint" not in jet
    assert adjoint["loss"] == pytest.approx(jet["loss"], rel=1e-12)
    for pointer in PARAMS:
        assert adjoint["gradient"][pointer] == pytest.approx(jet["gradient"][pointer], rel=1e-8)
    kept = adjoint["adjoint"]
    assert kept["steps"] >= 500 and kept["interval"] >= 1 and kept["memory_bytes"] > 0


def test_data_as_a_dataframe_or_a_trajectory(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    as_dict = tether.gradient(scene, data, PARAMS)
    as_frame = tether.gradient(scene, pandas.DataFrame(data), PARAMS)
    assert as_frame["gradient"] == as_dict["gradient"]
    own = scene.simulate(every=100)  # the run itself: loss zero
    assert tether.gradient(scene, own, "/bodies/0/mass")["loss"] == 0.0


def test_bad_data_and_parameters_are_input_errors(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    with pytest.raises(tether.InputError, match=r"data: unknown column 'bob.w'"):
        tether.gradient(scene, {"t": [0.1], "bob.w": [1.0]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"data: no 't' column"):
        tether.gradient(scene, {"bob.x": [1.0]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"data: row 2: t = 9 lies outside the simulated interval"):
        tether.gradient(scene, {"t": [0.1, 9.0], "bob.x": [1.0, 1.0]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"data: the columns have different lengths"):
        tether.gradient(scene, {"t": [0.1, 0.2], "bob.x": [1.0]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"/bodies/0/name: names string, not a number"):
        tether.gradient(scene, data, "/bodies/0/name")
    with pytest.raises(tether.InputError, match=r"method: unknown method 'reverse'"):
        tether.gradient(scene, data, PARAMS, method="reverse")
    with pytest.raises(tether.InputError, match=r"params: give at least one JSON Pointer"):
        tether.gradient(scene, data, [])
    with pytest.raises(tether.InputError, match=r"data: column 'bob.x': not all numbers"):
        tether.gradient(scene, {"t": [0.1], "bob.x": ["left"]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"data: column 'bob.x': expected one value per row"):
        tether.gradient(scene, {"t": [0.1, 0.2], "bob.x": [[1.0, 2.0], [3.0, 4.0]]}, PARAMS)
    with pytest.raises(tether.InputError, match=r"data: the column 't' appears twice"):
        tether.gradient(scene, pandas.DataFrame([[0.1, 0.2, 1.0]], columns=["t", "t", "bob.x"]), PARAMS)
    with pytest.raises(tether.InputError, match=r"data: expected a dict of arrays"):
        tether.gradient(scene, [[0.1, 1.0]], PARAMS)


def test_missing_values_in_a_dataframe_are_missing_observations(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    frame = pandas.DataFrame(data)
    frame.loc[2, "bob.vy"] = None  # NaN: not observed
    nullable = frame.astype({"bob.vy": "Float64"})  # pandas' own missing value, pandas.NA
    with_nan = tether.gradient(scene, frame, PARAMS)
    assert tether.gradient(scene, nullable, PARAMS)["gradient"] == with_nan["gradient"]
    assert with_nan["loss"] < tether.gradient(scene, data, PARAMS)["loss"]


def test_a_scene_that_cannot_be_assembled_is_named(tmp_path):
    document = tether.Scene.load(source("scenes", "four_bar.json")).to_dict()
    document["constraints"][0]["points"][0] = [5.0, 5.0]  # a pin moved far off: no assembly
    scene = tether.Scene.from_dict(document, name="moved_pin")
    with pytest.raises(tether.InputError, match=r"^moved_pin: .*"):
        scene.simulate(duration=0.01)
    with pytest.raises(tether.InputError, match=r"^moved_pin: .*"):
        tether.gradient(scene, {"t": [0.01], "crank0.x": [0.0]}, "/bodies/0/mass")


def test_a_wildcard_names_every_element_of_an_array(pendulum, observed):
    data, _ = observed
    scene = scene_with_velocity(pendulum)
    explicit = ["/bodies/0/velocity/0", "/bodies/0/velocity/1"]
    got = tether.gradient(scene, data, ["/bodies/0/velocity/*"])
    want = tether.gradient(scene, data, explicit)
    assert list(got["gradient"]) == explicit
    assert got["gradient"] == want["gradient"] and got["loss"] == want["loss"]
    with pytest.raises(tether.InputError, match=r"/bodies/0/mass/\*: '/\*' stands for the elements of an array"):
        tether.gradient(scene, data, ["/bodies/0/mass/*"])


def test_a_tie_makes_a_number_follow_the_parameters(pendulum, observed):
    """ties: the rod's length follows the mass (made up), so the gradient counts the length's change; the same as
    --tie, as a dict or as "PTR=EXPR" strings, and an unknown pointer is refused naming ties."""
    data, _ = observed
    free = tether.gradient(pendulum, data, ["/bodies/0/mass"])
    tied = tether.gradient(pendulum, data, ["/bodies/0/mass"], ties={"/constraints/0/length": "{/bodies/0/mass}*1.0"})
    as_text = tether.gradient(pendulum, data, ["/bodies/0/mass"], ties=["/constraints/0/length={/bodies/0/mass}*1.0"])
    assert tied == {**as_text, "seconds": tied["seconds"]}
    assert tied["gradient"]["/bodies/0/mass"] != free["gradient"]["/bodies/0/mass"]
    with pytest.raises(tether.InputError, match=r"ties '/constraints/0/length=\{/bodies/9/mass\}'.*/bodies/9/mass"):
        tether.gradient(pendulum, data, ["/bodies/0/mass"], ties={"/constraints/0/length": "{/bodies/9/mass}"})
