"""tether: constrained multibody dynamics in maximal coordinates, differentiable end to end.

The Python face of the C++ library (docs/python.md). A scene is loaded from a file or built from a dict and is
validated exactly as `tether` validates a file; it simulates into a Trajectory of NumPy arrays; gradient, tune,
identify, fit and check return what the command line prints as JSON, as Python objects; study runs a study file.
Data are tables: a dict of equal-length arrays, a pandas DataFrame or a Trajectory, with a `t` column and any
trajectory columns (NaN where a value is missing).

Errors are exceptions: InputError (a ValueError, naming the file or "<dict>" and the JSON Pointer, the row or
the argument at fault), SimulationDiverged (a RuntimeError: when and which constraint), OutputError (an OSError:
a file that could not be written), and KeyboardInterrupt when Ctrl-C stops a run (it stops at its next step; the
interpreter's lock is released while tether runs). An estimate that failed (identify, fit) is returned with
"failed": true and warned as EstimateFailed.
"""
import csv as _csv
import json as _json
import os as _os
import warnings as _warnings
from collections import namedtuple as _namedtuple
from collections.abc import Mapping as _Mapping

try:
    import numpy as _np
except ImportError as _missing:
    import sys as _sys

    raise ImportError(
        "tether's Python module needs NumPy, which the Python running it (%s, Python %d.%d) lacks. The module is "
        "built for Debian's /usr/bin/python3 with python3-numpy (docs/python.md): run it with /usr/bin/python3, "
        "or install NumPy for this interpreter (%s -m pip install numpy)"
        % (_sys.executable, _sys.version_info[0], _sys.version_info[1], _sys.executable)) from _missing

try:
    from . import _tether
except ImportError as _missing:
    import glob as _glob
    import sys as _sys

    raise ImportError(
        "tether's compiled part (%s) cannot be loaded by the Python running it (%s, Python %d.%d): it is built for "
        "Debian's /usr/bin/python3 (docs/python.md); run it with /usr/bin/python3, or build it for this "
        "interpreter (pip install --no-build-isolation . in the repository)"
        % (", ".join(_os.path.basename(p) for p in _glob.glob(_os.path.join(_os.path.dirname(__file__), "_tether*")))
           or "none found", _sys.executable, _sys.version_info[0], _sys.version_info[1])) from _missing
from ._tether import InputError, OutputError, SimulationDiverged
from ._tether import __version__  # the project's (CMakeLists.txt), as `tether --version` names it

__all__ = ["Scene", "Stepper", "Trajectory", "Event", "View", "view", "gradient", "tune", "identify", "fit", "check", "study", "InputError",
           "SimulationDiverged", "OutputError", "EstimateFailed"]
for _error in (InputError, OutputError, SimulationDiverged):
    _error.__module__ = __name__  # shown as tether.InputError


class EstimateFailed(UserWarning):
    """Warned by identify and fit when their result has "failed": true (the command line's exit status 1): the
    residuals are far above the data's noise, or the optimizer did not converge. The result is returned all the
    same, with its warnings and without standard deviations."""


def _json_text(document, name):
    """The scene as JSON text; NaN and infinities, which JSON lacks, are refused as a file's would be."""
    try:
        return _json.dumps(document, allow_nan=False)
    except ValueError:
        raise InputError(f"{name}: the scene holds NaN or an infinity, which JSON cannot") from None
    except TypeError as error:
        raise InputError(f"{name}: {error}") from None


def _tokens(pointer):
    """The reference tokens of a JSON Pointer (RFC 6901)."""
    if not isinstance(pointer, str) or not pointer.startswith("/"):
        raise InputError(f"{pointer!r}: not a JSON Pointer (it must look like /bodies/0/mass)")
    return [t.replace("~1", "/").replace("~0", "~") for t in pointer[1:].split("/")]


def _index(token):
    """An array index of a JSON Pointer: digits, without leading zeros (no negative index from the end)."""
    if not token.isdigit() or (len(token) > 1 and token[0] == "0"):
        raise ValueError(token)
    return int(token)


def _whole(value, name):
    """A count or a seed as the extension takes it (a C int): other values are the argument's InputError, not
    pybind11's TypeError."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise InputError(f"{name}: expected a whole number, got {value!r}")
    if not -2**31 <= value < 2**31:
        raise InputError(f"{name}: must be a whole number below 2^31 in size, got {value}")
    return int(value)


class Scene:
    """A validated scene: Scene.load(path) or Scene.from_dict(d)."""

    def __init__(self, core):
        self._core = core

    @classmethod
    def load(cls, path):
        """Reads and validates a scene file."""
        return cls(_tether.Scene.load(_os.fspath(path)))

    @classmethod
    def from_dict(cls, document, name="<dict>"):
        """Validates a scene given as Python objects, as a file is validated; `name` names it in messages."""
        return cls(_tether.Scene.parse(_json_text(document, name), name))

    @property
    def path(self):
        """The file the scene came from, or the name given to from_dict."""
        return self._core.path

    def to_dict(self):
        """The scene as Python objects (a new copy)."""
        return _json.loads(self._core.text())

    def set(self, pointer, value):
        """Sets the value at a JSON Pointer (which must exist) and validates the scene again; returns self."""
        document = self.to_dict()
        node, tokens = document, _tokens(pointer)
        try:
            for token in tokens[:-1]:
                node = node[_index(token)] if isinstance(node, list) else node[token]
            last = tokens[-1]
            if isinstance(node, list):
                node[_index(last)] = value
            elif last in node:
                node[last] = value
            else:
                raise KeyError(last)
        except (KeyError, IndexError, ValueError, TypeError):
            raise InputError(f"{self.path}: {pointer}: is not in the scene (a value left to its default must be "
                             "written out to be set)") from None
        self._core = _tether.Scene.parse(_json_text(document, self.path), self.path)
        return self

    def simulate(self, duration=None, step=None, integrator=None, every=1, *, alpha=None, beta=None,
                 stabilization=None, solver=None):
        """Runs the scene into a Trajectory, recording every `every`-th step. The other arguments, where given,
        replace the scene's settings as the command line's flags of the same names do: duration and step in s,
        integrator ("euler", "symplectic_euler", "rk4", "rk45"), alpha (1/s) and beta (1/s^2), which select the
        baumgarte method, stabilization ("none", "baumgarte", "projection") and solver ("auto", "dense",
        "sparse")."""
        overrides = _overrides(duration, step, integrator, alpha, beta, stabilization, solver)
        return Trajectory(_tether.simulate(self._core, overrides, _whole(every, "every")), self)

    def stepper(self, duration=None, step=None, integrator=None, every=1, *, alpha=None, beta=None,
                stabilization=None, solver=None):
        """A run that you step yourself, for a controller in Python (a Stepper, docs/stepping.md). It starts at the
        scene's initial state; the run ends at `duration` (the scene's, unless given). The arguments are
        simulate's."""
        return Stepper(self, _overrides(duration, step, integrator, alpha, beta, stabilization, solver),
                       _whole(every, "every"))

    def __repr__(self):
        return f"tether.Scene({self.path!r})"


def _overrides(duration, step, integrator, alpha, beta, stabilization, solver):
    overrides = _tether.SettingsOverrides()
    for name, value in (("duration", duration), ("step", step), ("integrator", integrator), ("alpha", alpha),
                        ("beta", beta), ("stabilization", stabilization), ("solver", solver)):
        setattr(overrides, name, value)
    return overrides


class Stepper:
    """A run taken step by step (Scene.stepper()): step(n) or step_to(t) advance it with the scene's integrator and
    step h; `t`, `q` and `v` are the state now (copies, in the model's layouts) and sim["COLUMN"] any trajectory
    column's value now; set_control(name, value) holds a
    joint_torque's value or a joint_servo's target from the next step on (name: the joint's, or /effects/K);
    state() and set_state(s) save and put back the whole state, controls included (resets, rollouts); trajectory()
    is the run so far as a Trajectory. Without set_control the trajectory is bit for bit simulate()'s. The
    interpreter's lock is released while it steps; Ctrl-C stops it at its next step."""

    def __init__(self, scene, overrides, every):
        self._scene = scene
        self._core = _tether.Stepper(scene._core, overrides, every)

    @property
    def t(self):
        """The time of the state now, s."""
        return self._core.t

    @property
    def end(self):
        """The time the run ends at (its duration), s."""
        return self._core.end

    @property
    def q(self):
        """The configuration now (a copy)."""
        return self._core.q

    @property
    def v(self):
        """The velocity now (a copy)."""
        return self._core.v

    def __getitem__(self, name):
        """A trajectory column's value now (sim["pivot.angle"]); columns() lists them."""
        return self._core.column(name)

    def columns(self):
        """The names of the trajectory's columns, as the CSV has them."""
        return list(self._core.columns())

    def step(self, n=1):
        """Takes n steps (none past the run's end: InputError, and no step taken); returns self."""
        self._core.step(_whole(n, "n"))
        return self

    def step_to(self, t):
        """Takes steps until the time reaches t (onto the first step's end at or after it); returns self."""
        self._core.step_to(float(t))
        return self

    def set_control(self, name, value):
        """Holds a joint_torque's value (N m or N) or a joint_servo's target (rad or m) from now on, in place of its
        schedule if it has one; returns self."""
        self._core.set_control(str(name), float(value))
        return self

    def control(self, name):
        """A control's value now."""
        return self._core.control(str(name))

    def state(self):
        """The whole state now (configuration, velocity, the integrator's and the events' memory, the controls):
        an opaque value for set_state."""
        return self._core.state()

    def set_state(self, state):
        """Puts back a state that state() returned; the trajectory is cut back to it (or, for a state of a rollout
        since abandoned, starts again at it); returns self."""
        self._core.set_state(state)
        return self

    def trajectory(self):
        """The run so far, as simulate() returns it."""
        return Trajectory(self._core.trajectory(), self._scene)

    def __repr__(self):
        return f"tether.Stepper({self._scene.path!r}, t={self.t!r})"


Event = _namedtuple("Event", ["t", "kind", "constraint", "speed_before", "speed_after", "point", "normal", "impulse"])
Event.__doc__ = """An event of a joint limit or a contact. Its first five fields are a row of `tether simulate
--events`: time (s), "impact", "release", "stick" or "slip", the joint's name (or /constraints/K) or the contact's
"SHAPE_A|SHAPE_B", and the gap's rate just before and after (rad/s or m/s, positive opening). Then where it
happened, in the world frame: `point` (a contact's point; a limit's joint point on its second body) and `normal`
(a contact's unit normal, from the second shape named towards the first, whose body the impulse pushes; zero for a
limit), and an impact's `impulse` along it (N s; for a limit N m s or N s along its coordinate; 0 for the other
kinds)."""


class Trajectory:
    """A run: every output row's time `t`, configuration `q` and velocity `v` (the model's layouts, rows x size),
    `constraint_error` and `energy`, and every CSV column by name (columns(), to_pandas()). The arrays are views of
    the memory the run filled. `events` is the table of the joint limits' and contacts' events (a list of Event rows,
    in time order; events_to_pandas() as a DataFrame)."""

    def __init__(self, recorded, scene=None):
        self._scene = scene
        self.events = [Event(*row) for row in recorded.events]
        self.table = recorded.table
        self.q = recorded.q
        self.v = recorded.v
        self._names = list(recorded.columns)
        self._index = {name: k for k, name in enumerate(self._names)}
        self.t = self["t"]
        self.constraint_error = self["constraint_error"]
        self.energy = self["energy"]

    @property
    def names(self):
        """The CSV's column names, in its order."""
        return list(self._names)

    def __getitem__(self, name):
        try:
            return self.table[:, self._index[name]]
        except KeyError:
            raise KeyError(f"no column {name!r} (the columns are {', '.join(self._names)})") from None

    def view(self):
        """The page of `tether view` that plays this run (a View: Jupyter shows it inline, save(path) writes it)."""
        if self._scene is None:
            raise InputError("this trajectory has no scene to draw: use tether.view(scene, trajectory)")
        return view(self._scene, self)

    def columns(self):
        """Every column by its CSV name, as views."""
        return {name: self.table[:, k] for k, name in enumerate(self._names)}

    def to_pandas(self):
        """A pandas DataFrame with the CSV's columns (needs pandas)."""
        import pandas
        return pandas.DataFrame(self.table, columns=self._names, copy=False)

    def events_to_pandas(self):
        """The events as a pandas DataFrame, a column per Event field (needs pandas)."""
        import pandas
        return pandas.DataFrame(self.events, columns=Event._fields)

    def __len__(self):
        return self.table.shape[0]


class View:
    """A page of `tether view` (docs/view.md): one self-contained HTML file that plays a run. Jupyter shows it
    inline (in a frame of its own); save(path) writes it; `html` is its text."""

    def __init__(self, html):
        self.html = html

    def _repr_html_(self):
        import html as _html
        return (f'<iframe srcdoc="{_html.escape(self.html, quote=True)}" '
                'style="width: 100%; height: 540px; border: 0"></iframe>')

    def save(self, path):
        """Writes the page to `path` (as `tether view -o` does); returns the path."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)
        return path


def view(scene, trajectory=None):
    """The page that plays `trajectory`, a Trajectory of `scene` (a Scene, a path or a dict), or the scene's own
    run when it is None, as `tether view` writes it."""
    if trajectory is None:
        trajectory = (scene if isinstance(scene, Scene) else
                      Scene.from_dict(scene) if isinstance(scene, _Mapping) else Scene.load(scene)).simulate()
    if not isinstance(trajectory, Trajectory):
        raise InputError("view: the trajectory must be a tether.Trajectory (Scene.simulate's)")
    events = [tuple(event) for event in trajectory.events]
    return View(_tether.view_html(_scene(scene), trajectory.table, trajectory.q, events))


def _scene(scene):
    if isinstance(scene, Scene):
        return scene._core
    if isinstance(scene, _Mapping):
        return Scene.from_dict(scene)._core
    return Scene.load(scene)._core


def _table(data, name):
    """(column names, rows x columns float array) of a table: a dict of arrays, a DataFrame or a Trajectory."""
    if isinstance(data, Trajectory):  # all its columns but constraint_error, a diagnostic nothing observes
        keep = [k for k, column in enumerate(data.names) if column != "constraint_error"]
        return [data.names[k] for k in keep], data.table[:, keep]
    if hasattr(data, "columns") and hasattr(data, "iloc"):  # a pandas DataFrame (its columns may repeat a name)
        pairs = [(str(label), data.iloc[:, k]) for k, label in enumerate(data.columns)]
    elif isinstance(data, _Mapping):
        pairs = [(str(label), column) for label, column in data.items()]
    else:
        raise InputError(f"{name}: expected a dict of arrays, a pandas DataFrame or a Trajectory, "
                         f"got {type(data).__name__}")
    columns = [_numbers(column, name, label) for label, column in pairs]
    if len({len(c) for c in columns}) > 1:
        raise InputError(f"{name}: the columns have different lengths")
    return [label for label, _ in pairs], _np.column_stack(columns) if columns else _np.zeros((0, 0))


def _numbers(column, name, label):
    """A column as a 1-D float array (a pandas Series' missing values as NaN)."""
    try:
        if hasattr(column, "to_numpy"):
            values = column.to_numpy(dtype=float, na_value=_np.nan)
        else:
            values = _np.asarray(column, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: column {label!r}: not all numbers") from None
    if values.ndim != 1:
        raise InputError(f"{name}: column {label!r}: expected one value per row, got an array of shape "
                         f"{values.shape}")
    return values


def _datasets(data):
    tables = data if isinstance(data, (list, tuple)) else [data]
    out = []
    for k, table in enumerate(tables):
        source = "data" if len(tables) == 1 else f"data[{k}]"
        names, values = _table(table, source)
        out.append(_tether.Dataset(source, names, values))
    return out


def _pointers(params):
    pointers = [params] if isinstance(params, str) else list(params)
    if not pointers:
        raise InputError("params: give at least one JSON Pointer")
    return pointers


def _ties(ties):
    """{pointer: expression} or ["PTR=EXPR", ...] as "PTR=EXPR" strings (as --tie)."""
    if ties is None:
        return []
    if isinstance(ties, _Mapping):
        return [f"{pointer}={expression}" for pointer, expression in ties.items()]
    if isinstance(ties, str):
        return [ties]
    return [str(tie) for tie in ties]


def _bounds(bounds):
    """{pointer: (lo, hi)} (None: unbounded) as (pointer, lo, hi) triples."""
    if bounds is None:
        return []
    if not isinstance(bounds, _Mapping):
        raise InputError(f"bounds: expected a dict of {{pointer: (lo, hi)}}, got {type(bounds).__name__}")
    out, big = [], _np.finfo(float).max
    for pointer, pair in bounds.items():
        try:
            lo, hi = pair
            out.append((pointer, -big if lo is None else float(lo), big if hi is None else float(hi)))
        except (TypeError, ValueError):
            raise InputError(f"bounds: {pointer!r}: expected (lo, hi), either None, got {pair!r}") from None
    return out


def gradient(scene, data, params, method="auto", ties=None):
    """The loss 1/2 sum (simulated - observed)^2 over the data and its gradient with respect to the parameters
    (JSON Pointers): {"loss", "gradient", "parameters", "method", "seconds"}, as `tether gradient` prints.
    method: "auto" (Jets for few parameters, the adjoint for many), "jet" (forward mode through the KKT solves),
    "adjoint" (reverse mode, the discrete adjoint) or "fd" (central differences); "method" in the result names the
    one used. ties: {pointer: expression} (or "PTR=EXPR" strings), numbers that follow others, as --tie
    ({"/bodies/1/inertia": "{/bodies/1/mass}*0.36/12"})."""
    names, values = _table(data, "data")
    return _json.loads(_tether.gradient(_scene(scene), names, values, _pointers(params), method, _ties(ties)))


def tune(scene, objective="reference", optimizer="ceres", samples=1, max_evaluations=200, *, duration=None, step=None,
         integrator=None, solver=None):
    """Tunes the Baumgarte gains for the scene's integrator and step, as `tether tune` (its JSON). duration, step,
    integrator and solver, where given, replace the scene's settings as in Scene.simulate and as tune's flags do;
    the gains and the stabilization are what it chooses."""
    overrides = _tether.SettingsOverrides()
    for name, value in (("duration", duration), ("step", step), ("integrator", integrator), ("solver", solver)):
        setattr(overrides, name, value)
    return _json.loads(_tether.tune(_scene(scene), overrides, objective, optimizer, _whole(samples, "samples"),
                                    _whole(max_evaluations, "max_evaluations")))


def _estimate(scene, data, params, bounds, segments, loss, optimizer, max_evaluations, smooth, method, ties,
              effort=0.0, at_least=None, at_most=None, starts=1, seed=1):
    result = _json.loads(_tether.identify(_scene(scene), [] if data is None else _datasets(data), _pointers(params),
                                         _bounds(bounds), _whole(segments, "segments"), loss or "", optimizer,
                                         _whole(max_evaluations, "max_evaluations"), smooth, method, _ties(ties),
                                         effort, _targets(at_least, "at_least"), _targets(at_most, "at_most"),
                                         _whole(starts, "starts"), _whole(seed, "seed")))
    if result["failed"]:  # where the command line exits with status 1
        _warnings.warn("the estimate failed: " + "; ".join(result["warnings"]), EstimateFailed, stacklevel=3)
    return result


def _targets(targets, name):
    if targets is None:
        return []
    if isinstance(targets, str):
        targets = [targets]
    if not all(isinstance(t, str) for t in targets):
        raise InputError(f"{name}: expected COLUMN=VALUE@T or COLUMN=VALUE@T0:T1 strings, e.g. ['tip.y=1.99@5']")
    return list(targets)


def identify(scene, data, params, bounds=None, segments=1, loss=None, optimizer="ceres", max_evaluations=200,
             method="auto", ties=None):
    """Estimates the parameters (JSON Pointers) from one recording or a list of them, as `tether identify` (its
    JSON: estimates, standard deviations, correlations, residuals, "failed"). bounds: {pointer: (lo, hi)}, either
    may be None; loss: None, "huber:DELTA" or "cauchy:DELTA"; method: the derivatives a gradient-based NLopt
    optimizer takes, "auto", "jet" or "adjoint" (as --method); ties as for gradient."""
    return _estimate(scene, data, params, bounds, segments, loss, optimizer, max_evaluations, 0.0, method, ties)


def fit(scene, data, params, bounds=None, segments=None, loss=None, optimizer=None, max_evaluations=None,
        smooth=0.0, method="auto", ties=None, effort=0.0, at_least=None, at_most=None, starts=1, seed=1):
    """Fits initial conditions or schedules to targets, as `tether fit` (smooth: the weight of the penalty on
    changes between schedule values; method and ties as for identify). Trajectory optimisation: effort (the weight
    of the integral of the squared motor torques), at_least / at_most (constraints, "COLUMN=VALUE@T" or
    "COLUMN=VALUE@T0:T1" strings as the flags take), starts and seed; data may be None when there are constraints.
    segments=None lets fit choose, as the command line does. The optimizer defaults to ceres, or nlopt:LD_SLSQP
    with constraints or starts; max_evaluations to 200, or 1000 with constraints or starts."""
    trajectory = bool(at_least) or bool(at_most) or starts > 1
    if optimizer is None:
        optimizer = _tether.TRAJECTORY_OPTIMIZER if trajectory else "ceres"
    if max_evaluations is None:
        max_evaluations = _tether.TRAJECTORY_MAX_EVALUATIONS if trajectory else 200
    if data is None and not trajectory:
        raise InputError("data: fit needs targets: data, or constraints (at_least, at_most)")
    return _estimate(scene, data, params, bounds, -1 if segments is None else segments, loss, optimizer,
                     max_evaluations, smooth, method, ties, effort, at_least, at_most, starts, seed)


def check(scene):
    """Degrees of freedom, rank, redundant constraints, initial violation and conditioning, as `tether check
    --json`."""
    return _json.loads(_tether.check(_scene(scene)))


def _cell(text):
    try:
        return float(text)
    except ValueError:
        return text


def study(path, out, threads=None, restart=False):
    """Runs (or resumes) the study file `path` into the folder `out`, as `tether study` does (results.csv, without
    the figures and summary.md the command line adds), and returns results.csv's rows as dicts."""
    threads = (_os.cpu_count() or 1) if threads is None else threads
    _tether.study(_os.fspath(path), _os.fspath(out), _whole(threads, "threads"), restart)
    with open(_os.path.join(_os.fspath(out), "results.csv"), newline="") as f:
        return [{k: _cell(v) for k, v in row.items()} for row in _csv.DictReader(f)]
