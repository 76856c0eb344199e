"""Ctrl-C during a long run raises KeyboardInterrupt at once, and the module works on after it."""
import json
import os
import signal
import threading
import time

import pytest

import tether
from conftest import source


def test_ctrl_c_stops_a_long_run_and_the_module_goes_on():
    scene = tether.Scene.load(source("scenes", "chain100.json"))
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        scene.simulate(duration=1000.0, every=1000000)  # hours, were it not stopped
    assert time.monotonic() - start < 5.0
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # Python's handler is back
    assert len(scene.simulate(duration=0.01)) == 11  # and a run goes to its end again


def test_runs_in_several_threads_stop_together_and_python_handles_ctrl_c_after():
    scene = tether.Scene.load(source("scenes", "chain100.json"))
    outcomes = []

    def run():
        try:
            scene.simulate(duration=1000.0, every=1000000)
            outcomes.append("finished")
        except KeyboardInterrupt:
            outcomes.append("interrupted")

    threads = [threading.Thread(target=run) for _ in range(2)]
    for thread in threads:
        thread.start()
    time.sleep(0.5)
    os.kill(os.getpid(), signal.SIGINT)
    for thread in threads:
        thread.join(timeout=10.0)
    assert outcomes == ["interrupted", "interrupted"]
    with pytest.raises(KeyboardInterrupt):  # Python's own handling of SIGINT is back, whole
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)


def test_a_second_ctrl_c_does_not_end_the_interpreter():
    scene = tether.Scene.load(source("scenes", "chain100.json"))
    timer = threading.Timer(0.5, lambda: [os.kill(os.getpid(), signal.SIGINT) for _ in range(3)])
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        scene.simulate(duration=1000.0, every=1000000)
    assert len(scene.simulate(duration=0.01)) == 11


def test_ctrl_c_in_a_study_keeps_no_row_it_stopped(tmp_path):
    spec = tmp_path / "study.json"
    spec.write_text(json.dumps({"scene": source("scenes", "chain100.json"),
                                "sweep": {"/simulation/duration": [0.05, 0.06, 0.07, 0.08],
                                          "/stabilization/method": ["tuned"]},
                                "metrics": ["max_constraint_error"]}))
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        tether.study(spec, tmp_path / "out", threads=1)
    rows = tether.study(spec, tmp_path / "out", threads=1)  # resumed: every row measured, none "failed"
    assert [r["status"] for r in rows] == ["ok"] * 4
