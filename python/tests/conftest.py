"""Shared helpers: the tether executable and the repository (set by ctest and scripts/dev), a run of the command
line, and its CSV read back as numbers."""
import csv
import json
import os
import subprocess

import pytest

ROOT = os.environ.get("TETHER_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
EXECUTABLE = os.environ.get("TETHER_EXECUTABLE", os.path.join(ROOT, "build", "tether"))


def source(*parts):
    return os.path.join(ROOT, *parts)


def cli(*args):
    """Runs `tether ARGS`; returns its stdout (it must succeed)."""
    done = subprocess.run([EXECUTABLE, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def cli_json(*args):
    return json.loads(cli(*args))


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_csv(path):
    """(header, rows of floats) of a trajectory CSV."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in row] for row in rows[1:]]


@pytest.fixture
def pendulum():
    return source("scenes", "pendulum.json")
