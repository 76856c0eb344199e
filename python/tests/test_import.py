"""What `import tether` gives: tether's own names only, and, on a Python that cannot load it, a message saying
which Python the module is for and what to do."""
import os
import subprocess
import sys

import tether


def test_the_namespace_holds_only_tethers_names():
    public = {name for name in dir(tether) if not name.startswith("_")}
    assert public == set(tether.__all__)  # no numpy, json, os, csv, warnings, namedtuple or Mapping


def test_a_python_without_numpy_is_told_which_python_the_module_is_for(tmp_path):
    fake = tmp_path / "numpy"
    fake.mkdir()
    (fake / "__init__.py").write_text('raise ImportError("No module named numpy")\n')
    module = os.path.dirname(os.path.dirname(tether.__file__))
    done = subprocess.run([sys.executable, "-c", "import tether"], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), module])})
    assert done.returncode != 0
    message = done.stderr.strip().splitlines()[-1]
    assert "tether's Python module needs NumPy" in message
    assert sys.executable in message and "/usr/bin/python3" in message and "pip install numpy" in message
