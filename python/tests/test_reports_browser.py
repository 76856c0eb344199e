"""`identify --report`, `fit --report` and a study's index.html (docs/reports.md) in headless Chromium: a report draws
every column, its residuals and their histogram, the parameters and their correlations, and plays the estimate's
motion, with a clean console; its residual statistics are those of the estimate's own run, computed here from
`tether simulate`. A study's index sorts its rows and plays any run that finished."""
import csv
import json
import os
import re
import subprocess

import numpy
import pytest

from browser import page_probe
from conftest import EXECUTABLE, read_csv, source

ARM = ["identify", source("docs", "examples", "arm", "guess.json"), "--data",
       source("docs", "examples", "arm", "encoders.csv"), "--param", "/bodies/1/mass", "--param",
       "/bodies/1/inertia/1", "--param", "/bodies/1/inertia/2", "--param", "/effects/1/damping"]


def report_of(tmp_path, args):
    """Runs tether ARGS --report; returns (the page's path, the JSON the page draws)."""
    page = tmp_path / "report.html"
    done = subprocess.run([EXECUTABLE, *args, "--quiet", "--report", page], capture_output=True, text=True)
    if done.returncode == 2 and "built without the viewer" in done.stderr:
        pytest.skip("this build has no viewer (-DTETHER_VIEWER=OFF)")
    assert done.returncode == 0, done.stderr
    text = page.read_text(encoding="utf-8")
    data = re.search(r'<script type="application/json" id="tether-report">(.*?)</script>', text, re.S).group(1)
    return page, json.loads(data.replace("<\\/", "</"))


def test_an_identification_s_report_draws_every_column_and_its_residuals(tmp_path):
    page, report = report_of(tmp_path, ARM + ["-o", tmp_path / "estimate.json"])
    drawn = page_probe(page, "tether-report-probe")
    assert drawn["parameters"] == 4 and drawn["correlations"] == 16
    assert drawn["columns"] == 2 and drawn["histograms"] == [150, 150]  # every residual in a bin
    assert drawn["warnings"] == 0 and drawn["constraints"] == 0
    # the statistics are those of one run of the estimate: tether simulate of the scene it wrote, at the data's times
    subprocess.run([EXECUTABLE, "simulate", tmp_path / "estimate.json", "-o", tmp_path / "run.csv"], check=True)
    header, rows = read_csv(tmp_path / "run.csv")
    run = numpy.array(rows)
    data_header, data_rows = read_csv(source("docs", "examples", "arm", "encoders.csv"))
    data = numpy.array(data_rows)
    for column in report["columns"]:
        simulated = numpy.interp(data[:, 0], run[:, 0], run[:, header.index(column["column"])])
        r = simulated - data[:, data_header.index(column["column"])]
        s = column["statistics"]
        lag_one = numpy.sum((r[:-1] - r.mean()) * (r[1:] - r.mean())) / numpy.sum((r - r.mean()) ** 2)
        assert s["count"] == len(r)
        assert s["rms"] == pytest.approx(numpy.sqrt(numpy.mean(r ** 2)), rel=1e-6)
        assert s["bias"] == pytest.approx(r.mean(), abs=1e-6 * s["rms"])
        assert s["lag_one"] == pytest.approx(lag_one, abs=1e-5)
        assert column["fit_rms"] == pytest.approx(s["rms"], rel=1e-6)  # single shooting: the fit's own run
        assert abs(s["lag_one"]) < 0.5  # the encoders' noise is white: the model is right
    assert report["pointers"] == ["/bodies/1/mass", "/bodies/1/inertia/1", "/bodies/1/inertia/2", "/effects/1/damping"]
    assert 'srcdoc="&lt;!doctype html&gt;' in page.read_text(encoding="utf-8")  # the motion, in its frame


def test_a_trajectory_fit_s_report_draws_its_constraints(tmp_path):
    page, report = report_of(tmp_path, [
        "fit", source("docs", "examples", "swing_up", "pendulum.json"), "--param", "/effects/1/schedule/values/*",
        "--bound", "/effects/1/schedule/values/*=-2:2", "--effort", "0.1", "--at-least", "axle.angle=3@3",
        "--at-most", "axle.angle=3.3@3", "--at-least", "axle.omega=-0.2@3", "--at-most", "axle.omega=0.2@3",
        "--starts", "2"])
    drawn = page_probe(page, "tether-report-probe")
    assert drawn["columns"] == 0 and drawn["constraints"] == 4 and drawn["constrained"] == 2
    assert drawn["parameters"] == 13 and drawn["correlations"] == 0  # a fit to constraints has no uncertainty
    assert drawn["schedules"] == 1 and len(report["schedules"][0]["values"]) == 13  # the motor's knots
    assert [c["met"] for c in report["constraints"]] == [True] * 4


def test_a_report_that_cannot_be_written_is_refused_before_the_work(tmp_path):
    done = subprocess.run([EXECUTABLE, *ARM, "--report", tmp_path / "missing" / "report.html"], capture_output=True,
                          text=True)
    assert done.returncode == 2 and "--report" in done.stderr and done.stdout == ""


def test_a_study_s_index_sorts_its_rows_and_plays_any_of_them(tmp_path):
    """A study of the pendulum over step and stabilization (two runs diverge): index.html sorted by a metric, with
    the diverged runs last, plays the row it is asked for; a diverged row has no view."""
    study = tmp_path / "study.json"
    study.write_text(json.dumps({
        "scene": source("scenes", "pendulum.json"),
        "sweep": {"/simulation/integrator": ["euler"], "/simulation/step": [0.01, 0.002],
                  "/stabilization/beta": [400.0, 1.0e8], "/stabilization/alpha": [20.0],
                  "/simulation/duration": [1.0]},
        "metrics": ["max_constraint_error"]}))
    out = tmp_path / "out"
    done = subprocess.run([EXECUTABLE, "study", study, "--out", out, "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    if not (out / "index.html").exists():
        pytest.skip("this build has no viewer (-DTETHER_VIEWER=OFF)")
    with open(out / "results.csv", newline="") as f:
        lines = list(csv.reader(f))[1:]
    errors = [float(line[5]) for line in lines]  # nan for a diverged run
    finished = [k for k, e in enumerate(errors) if e == e]
    assert finished == [0, 2], lines  # beta = 1e8 runs away with euler
    shown = page_probe(out / "index.html", "tether-study-probe", f"#sort=-max_constraint_error&row={finished[0]}")
    assert shown["rows"] == shown["shown"] == 4 and shown["figures"] == 1
    by_error = sorted(finished, key=lambda k: -errors[k]) + [k for k in range(4) if k not in finished]
    assert shown["order"] == by_error
    assert shown["viewing"] == finished[0] and shown["loaded"] == {"row": finished[0], "frames": 31}  # 30 a second
    diverged = next(k for k in range(4) if k not in finished)
    assert page_probe(out / "index.html", "tether-study-probe", f"#row={diverged}")["viewing"] == -1


SHIPPED_INDEXES = ["studies/accuracy/results", "studies/stability_maps/results", "studies/optimizers/results",
                   "studies/gradient_cost", "studies/scaling"]


@pytest.mark.parametrize("folder", SHIPPED_INDEXES)
def test_every_shipped_study_has_a_current_index(folder):
    """Each shipped study's index.html opens with a clean console, holds every row of its results, and carries
    today's study.js (a page left behind by a change to it would say so here: regenerate the study)."""
    page = source(folder, "index.html")
    with open(page, encoding="utf-8") as f:
        text = f.read()
    with open(source("viewer", "assets", "study.js"), encoding="utf-8") as f:
        assert "<script>" + f.read() + "</script>" in text, "regenerate " + folder + "/index.html"
    study = json.loads(re.search(r'<script type="application/json" id="tether-study">(.*?)</script>', text,
                                 re.S).group(1).replace("<\\/", "</"))
    shown = page_probe(page, "tether-study-probe", "#sort=-" + study["metrics"][0])
    assert shown["rows"] == shown["shown"] == len(study["rows"]) > 0 and shown["figures"] >= 1
    values = [study["rows"][k]["metrics"][0] for k in shown["order"]]
    numbers = [v for v in values if v is not None]
    assert numbers == sorted(numbers, reverse=True) and values[:len(numbers)] == numbers  # nan last


def test_a_scripted_study_s_index_is_its_results(tmp_path):
    """studies/index_page.py rewrites the scaling study's page from its results.json: the one in the repository."""
    import shutil
    import sys
    sys.path.insert(0, source("studies"))
    import index_page
    for name in ("results.json", "scaling.png"):
        shutil.copy(source("studies", "scaling", name), tmp_path / name)
    written = index_page.write_index("scaling", str(tmp_path))
    with open(written, encoding="utf-8") as f, open(source("studies", "scaling", "index.html"), encoding="utf-8") as g:
        assert f.read() == g.read()


def readme_fits():
    """The README's `tether identify` and `tether fit` commands, as argument lists (continuation lines joined).
    Two are left to other tests: the imported humanoid's (tests/import/mujoco_cli_test.cc writes its report) and
    the acrobot's swing-up, 23 s of fitting (docs/reports.md)."""
    import shlex
    with open(source("README.md"), encoding="utf-8") as f:
        text = f.read().replace("\\\n", " ")
    commands = []
    for line in text.splitlines():
        if re.match(r"build/tether (identify|fit) ", line) and "humanoid.json" not in line and "acrobot" not in line:
            commands.append(shlex.split(line.split("  #")[0])[1:])
    return commands


@pytest.mark.parametrize("args", readme_fits(), ids=lambda args: os.path.basename(args[1]))
def test_every_readme_fit_writes_its_report(tmp_path, args):
    files = {"-o": tmp_path / "estimate.json", "--plot": tmp_path / "fit.png"}  # the README's outputs, put aside
    args = [str(files.get(args[k - 1], a)) if k else a for k, a in enumerate(args)]
    args = [source(a) if os.path.exists(source(a)) else a for a in args]
    page, report = report_of(tmp_path, args)
    drawn = page_probe(page, "tether-report-probe")
    assert drawn["parameters"] == len(report["pointers"]) > 0
    assert drawn["columns"] == len(report["columns"]) and drawn["constraints"] == len(report.get("constraints", []))
    assert drawn["columns"] + drawn["constraints"] > 0
