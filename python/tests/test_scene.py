"""tether.Scene: loading, building from a dict (validated as a file is, errors naming the JSON Pointer), to_dict
and set."""
import json

import pytest

import tether
from conftest import cli, read_json, source


def test_load_and_to_dict_give_the_file(pendulum):
    scene = tether.Scene.load(pendulum)
    assert scene.path == pendulum
    assert scene.to_dict() == read_json(pendulum)
    assert repr(scene) == f"tether.Scene({pendulum!r})"


def test_from_dict_validates_as_a_file_is(pendulum):
    document = read_json(pendulum)
    assert tether.Scene.from_dict(document).to_dict() == document
    document["bodies"][0]["mass"] = -1
    with pytest.raises(tether.InputError, match=r"<dict>: /bodies/0/mass: must be > 0, got -1"):
        tether.Scene.from_dict(document)
    document["bodies"][0]["mass"] = 1
    document["bodies"][0]["colour"] = "red"
    with pytest.raises(tether.InputError, match=r"/bodies/0/colour: unknown key 'colour'"):
        tether.Scene.from_dict(document, name="mine")
    with pytest.raises(ValueError):  # InputError is a ValueError
        tether.Scene.from_dict({"bodies": []})


def test_set_changes_the_scene_and_validates_it(pendulum):
    scene = tether.Scene.load(pendulum)
    assert scene.set("/bodies/0/mass", 2.5) is scene
    assert scene.to_dict()["bodies"][0]["mass"] == 2.5
    with pytest.raises(tether.InputError, match=r"/bodies/0/mass: must be > 0, got 0"):
        scene.set("/bodies/0/mass", 0.0)
    assert scene.to_dict()["bodies"][0]["mass"] == 2.5  # a refused value leaves the scene as it was
    with pytest.raises(tether.InputError, match=r"/bodies/0/charge: is not in the scene"):
        scene.set("/bodies/0/charge", 1.0)
    with pytest.raises(tether.InputError, match=r"not a JSON Pointer"):
        scene.set("bodies/0/mass", 1.0)
    with pytest.raises(tether.InputError, match=r"/bodies/-1/mass: is not in the scene"):  # no index from the end
        scene.set("/bodies/-1/mass", 1.0)
    with pytest.raises(tether.InputError, match=r"the scene holds NaN or an infinity"):
        scene.set("/bodies/0/mass", float("nan"))
    with pytest.raises(tether.InputError, match=r"<dict>: the scene holds NaN or an infinity"):
        tether.Scene.from_dict({"bodies": [{"mass": float("inf")}]})


def test_a_missing_file_is_an_input_error():
    with pytest.raises(tether.InputError, match=r"cannot"):
        tether.Scene.load(source("scenes", "no_such_scene.json"))


def test_version_is_the_command_line_s_and_the_package_s():
    assert cli("--version").split()[1] == tether.__version__
    with open(source("pyproject.toml")) as f:
        assert f'version = "{tether.__version__}"' in f.read()
