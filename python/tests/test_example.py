"""The README's Python example is docs/examples/identify/identify.py (in README.md and docs/python.md as it is in
the file); it runs and prints the command line's numbers, as README.md quotes them."""
import json
import os
import subprocess
import sys

import tether
from conftest import cli, source


def test_the_readme_example_gives_the_cli_numbers(tmp_path):
    os.symlink(os.path.abspath(source("docs")), tmp_path / "docs")  # the script runs from the repository's root
    package = os.path.dirname(os.path.dirname(os.path.abspath(tether.__file__)))  # the tether under test
    environment = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=package)
    done = subprocess.run([sys.executable, source("docs", "examples", "identify", "identify.py")], cwd=tmp_path,
                          capture_output=True, text=True, env=environment)
    assert done.returncode == 0, done.stderr
    expected = json.loads(cli("identify", source("docs", "examples", "identify", "guess.json"), "--data",
                              source("docs", "examples", "identify", "recording.csv"), "--param", "/bodies/1/mass",
                              "--segments", "6"))
    assert done.stdout == f"{expected['parameters']} {expected['standard_deviation']} {expected['evaluations']}\n"
    assert (tmp_path / "fit.png").stat().st_size > 10000
    with open(source("docs", "examples", "identify", "identify.py")) as f:
        script = f.read()
    for document in ("README.md", os.path.join("docs", "python.md")):
        with open(source(document)) as f:
            text = f.read()
        assert "```python\n" + script + "```" in text, document
    with open(source("README.md")) as f:
        assert "```\n" + done.stdout + "```" in f.read()
