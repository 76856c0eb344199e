"""Fuzzing the Python entry points (issue 34): random values of the right Python types through Scene.from_dict,
Scene.set, Scene.simulate, gradient, identify, fit and tune. Each call returns, or raises tether.InputError
(naming the argument or the pointer) or tether.SimulationDiverged; anything else (another exception, a crash of
the interpreter) is a finding. Hypothesis (Debian's python3-hypothesis) draws the cases, derandomized so that CI
sees the same ones every run: 200 cases an entry point, 1400 in all, in a few seconds."""
import atexit
import math
import shutil
import tempfile

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.configuration import set_hypothesis_home_dir

HYPOTHESIS_HOME = tempfile.mkdtemp(prefix="tether-hypothesis-")  # its caches stay out of the tree, and go after
set_hypothesis_home_dir(HYPOTHESIS_HOME)
atexit.register(shutil.rmtree, HYPOTHESIS_HOME, True)

import tether
from conftest import source

ALLOWED = (tether.InputError, tether.SimulationDiverged)
FUZZ = settings(max_examples=200, deadline=None, derandomize=True, database=None,  # nothing written to the tree
               suppress_health_check=list(HealthCheck))

PENDULUM = tether.Scene.load(source("scenes", "pendulum.json"))
GUESS = source("docs", "examples", "identify", "guess.json")

# numbers at the edges of their domains, and ordinary ones
edges = st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300, math.inf, -math.inf, math.nan, 1e-12, -1.0,
                         2.0**31, 2.0**63])
numbers = st.one_of(edges, st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**20, 10**20))
# JSON Pointers: the scene's own, mangled, and random text
known = st.sampled_from(["/bodies/0/mass", "/bodies/0/position/0", "/constraints/0/length", "/effects/0/acceleration/1",
                         "/simulation/step", "/simulation/duration", "/stabilization/alpha", "/bodies/*/mass"])
pointers = st.one_of(known, known.map(lambda p: p + "/0"), known.map(lambda p: p.replace("0", "99999999999999999999")),
                     st.text(max_size=30).map(lambda t: "/" + t), st.text(max_size=10))
json_values = st.recursive(st.one_of(st.none(), st.booleans(), numbers, st.text(max_size=8)),
                           lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                   st.dictionaries(st.text(max_size=8), inner, max_size=4)),
                           max_leaves=12)
column_names = st.one_of(st.sampled_from(["t", "bob.x", "bob.y", "bob.vx", "bob.vy", "energy", "constraint_error",
                                          "bob.x ", "\ufeffbob.x", "bob,x", "bob.z"]), st.text(max_size=8))


def call(function, *args, **kwargs):
    try:
        function(*args, **kwargs)
    except ALLOWED:
        pass


@FUZZ
@given(key=st.sampled_from(["bodies", "constraints", "effects", "simulation", "stabilization", "dimension",
                            "markers", "shapes"]), value=json_values)
def test_scene_from_dict(key, value):
    document = PENDULUM.to_dict()
    document[key] = value
    call(tether.Scene.from_dict, document)


@FUZZ
@given(pointer=pointers, value=json_values)
def test_scene_set(pointer, value):
    call(tether.Scene.load(source("scenes", "pendulum.json")).set, pointer, value)


@FUZZ
@given(duration=st.one_of(st.none(), numbers), step=st.one_of(st.none(), numbers), every=st.integers(-3, 10**12),
       integrator=st.one_of(st.none(), st.sampled_from(["rk4", "euler", "rk45", "symplectic_euler", "", "RK4"])),
       alpha=st.one_of(st.none(), numbers), solver=st.one_of(st.none(), st.sampled_from(["auto", "dense", "x"])))
def test_simulate(duration, step, every, integrator, alpha, solver):
    # the run's size is bounded before it starts; keep the accepted ones short
    if duration is not None and not (isinstance(duration, float) and duration < 0.05):
        duration = 0.05
    if step is not None and isinstance(step, (int, float)) and 0 < step < 1e-4:
        step = 1e-4
    call(PENDULUM.simulate, duration=duration, step=step, integrator=integrator, every=every, alpha=alpha,
         solver=solver)


tables = st.dictionaries(column_names, st.lists(numbers, min_size=0, max_size=5), min_size=0, max_size=4)


@FUZZ
@given(data=tables, params=st.lists(pointers, min_size=0, max_size=3),
       method=st.sampled_from(["auto", "jet", "adjoint", "fd", "reverse"]))
def test_gradient(data, params, method):
    lengths = {len(v) for v in data.values()}
    if len(lengths) == 1 and "t" in data:  # equal-length columns reach the reader's own checks
        data["t"] = [abs(x) % 1.0 if isinstance(x, float) and math.isfinite(x) else x for x in data["t"]]
    call(tether.gradient, PENDULUM, {k: np.array(v, dtype=float) for k, v in data.items()}, params, method=method)


@FUZZ
@given(params=st.lists(pointers, min_size=0, max_size=2),
       bounds=st.dictionaries(pointers, st.tuples(st.one_of(st.none(), numbers), st.one_of(st.none(), numbers)),
                              max_size=2),
       segments=st.integers(-2, 200000), loss=st.one_of(st.none(), st.sampled_from(["huber:0.1", "cauchy:-1", "x"])),
       max_evaluations=st.integers(-5, 4))
def test_identify(params, bounds, segments, loss, max_evaluations):
    data = {"t": np.array([0.5, 1.0]), "p0.x": np.array([0.8, 0.7])}
    call(tether.identify, GUESS, data, params, bounds=bounds, segments=segments, loss=loss,
         max_evaluations=max_evaluations)


@FUZZ
@given(at_least=st.lists(st.text(max_size=20), max_size=2), starts=st.integers(-1, 3), effort=numbers,
       smooth=numbers)
def test_fit(at_least, starts, effort, smooth):
    call(tether.fit, source("docs", "examples", "swing_up", "pendulum.json"), None,
         ["/effects/1/schedule/values/0"], at_least=at_least, starts=starts, effort=effort, smooth=smooth,
         max_evaluations=4)


@FUZZ
@given(objective=st.sampled_from(["reference", "drift", "", "speed"]), samples=st.integers(-1, 3),
       max_evaluations=st.integers(-1, 4), step=st.one_of(st.none(), numbers),
       integrator=st.one_of(st.none(), st.sampled_from(["rk4", "euler", "nope"])))
def test_tune(objective, samples, max_evaluations, step, integrator):
    if step is not None and isinstance(step, (int, float)) and 0 < step < 1e-3:
        step = 1e-3
    call(tether.tune, PENDULUM, objective=objective, samples=samples, max_evaluations=max_evaluations, step=step,
         integrator=integrator, duration=0.2)
