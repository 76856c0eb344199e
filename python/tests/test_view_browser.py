"""`tether view` in a real browser (docs/view.md): Debian's headless Chromium opens the page with the network off;
the console stays clean, the page draws the bodies where the trajectory puts them, two times look different where a
body moves, and the slider's last frame is the CSV's last row. Without a browser these tests fail (the README's test
command installs chromium-headless-shell); they are skipped only when tether was built without the viewer."""
import glob
import os
import re
import subprocess

import pytest

from browser import BACKGROUND, HEIGHT, WIDTH, browse, browser_screenshot, page_probe
from conftest import EXECUTABLE, read_csv, source


def view(tmp_path, scene, *flags):
    """Writes the page of `scene`; returns its path (skips when the build has no viewer)."""
    page = tmp_path / "view.html"
    done = subprocess.run([EXECUTABLE, "view", scene, "-o", page, *flags], capture_output=True, text=True)
    if done.returncode == 2 and "built without the viewer" in done.stderr:
        pytest.skip("this build has no viewer (-DTETHER_VIEWER=OFF)")
    assert done.returncode == 0, done.stderr
    return page


def probe(page, seconds):
    """The page's own report at time SECONDS: the frame shown and the bodies' origins in pixels."""
    return page_probe(page, "tether-probe", f"#t={seconds}")


def screenshot(page, seconds, tmp_path):
    return browser_screenshot(page, f"#t={seconds}", tmp_path / f"shot_{seconds}.png")


def test_the_robot_arm_plays_where_its_trajectory_puts_it(tmp_path):
    page = view(tmp_path, source("scenes", "robot_arm.json"))
    early, late = probe(page, 0.2), probe(page, 0.9)
    assert early["plotted"] == "a1.angle"  # a joint's coordinate beside the view
    assert early["frame"] < late["frame"] and abs(early["time"] - 0.2) <= 1 / 60 and abs(late["time"] - 0.9) <= 1 / 60
    first, second = screenshot(page, 0.2, tmp_path), screenshot(page, 0.9, tmp_path)
    moved = 0
    for at in (early, late):
        image = first if at is early else second
        for x, y in at["bodies"]:
            pixel = image[int(round(y)), int(round(x))]
            assert abs(pixel - BACKGROUND).max() > 0.05, f"nothing drawn at a body's origin ({x:.0f}, {y:.0f})"
    for (x0, y0), (x1, y1) in zip(early["bodies"], late["bodies"]):
        moved += abs(x1 - x0) + abs(y1 - y0) > 5
    assert moved > 0, "no body moved on the screen between 0.2 s and 0.9 s"
    assert abs(first - second).max() > 0.2, "the two times look the same"


def test_the_last_frame_is_the_data_s_last_row(tmp_path):
    csv = tmp_path / "arm.csv"
    subprocess.run([EXECUTABLE, "simulate", source("scenes", "robot_arm.json"), "-o", csv], check=True)
    _, rows = read_csv(csv)
    page = view(tmp_path, source("scenes", "robot_arm.json"), "--data", csv)
    end = probe(page, 1e9)
    assert end["frame"] == end["frames"] - 1 and end["time"] == rows[-1][0]


def test_a_planar_scene_is_drawn_in_its_plane(tmp_path):
    page = view(tmp_path, source("scenes", "four_bar.json"))
    at = probe(page, 0.5)
    image = screenshot(page, 0.5, tmp_path)
    for x, y in at["bodies"]:
        assert 0 <= x < WIDTH and 0 <= y < HEIGHT
        assert abs(image[int(round(y)), int(round(x))] - BACKGROUND).max() > 0.05


def test_a_bouncing_ball_s_impacts_are_listed_and_marked(tmp_path):
    scene = source("docs", "examples", "contact", "ball.json")
    events = tmp_path / "events.csv"
    subprocess.run([EXECUTABLE, "simulate", scene, "-o", tmp_path / "ball.csv", "--events", events], check=True)
    with open(events) as f:
        impacts = [line for line in f.read().splitlines()[1:] if ",impact," in line]
    assert len(impacts) >= 3
    page = view(tmp_path, scene)
    dom, console = browse(page, "#t=0.5", "--dump-dom")
    assert console == [], console
    listed = re.search(r'<ol id="tether-events">(.*?)</ol>', dom, re.S).group(1)
    assert listed.count("<li>") == len(impacts) and listed.count("impact  ball_surface|floor") == len(impacts)
    marks = re.search(r'<datalist id="tether-marks">(.*?)</datalist>', dom, re.S).group(1)
    assert marks.count("<option") == len(impacts)
    assert probe(page, 0.5)["plotted"] == "energy"  # no joint: the energy, which each impact lowers
    # the first impact's place: shown from its frame for a quarter of a second, under the ball, drawn
    first = float(impacts[0].split(",")[0])
    at = probe(page, first + 0.05)
    assert len(at["places"]) == 1
    (x, y), (ball_x, ball_y) = at["places"][0], at["bodies"][0]
    assert abs(x - ball_x) < 2 and y > ball_y + 5  # z is up on the screen
    image = screenshot(page, first + 0.05, tmp_path)
    assert abs(image[int(round(y)), int(round(x))] - BACKGROUND).max() > 0.05
    assert probe(page, first + 0.3)["places"] == []
    assert f"P = " in listed  # each impact's impulse


def test_python_s_view_is_the_command_s_page_and_shows_inline(tmp_path):
    import tether
    scene = source("scenes", "robot_arm.json")
    page = view(tmp_path, scene)
    shown = tether.Scene.load(scene).simulate().view()
    with open(page, encoding="utf-8") as f:
        assert shown.html == f.read()  # the same frames, series and events as the command's
    assert tether.view(scene).html == shown.html
    assert shown._repr_html_().startswith('<iframe srcdoc="&lt;!doctype html&gt;')
    saved = shown.save(tmp_path / "saved.html")
    assert probe(saved, 0.5)["frame"] == 30
    with pytest.raises(tether.InputError, match="not a run of this scene"):
        tether.view(source("scenes", "pendulum.json"), tether.Scene.load(scene).simulate())


def test_a_recording_is_drawn_as_ghosts_beside_the_simulation(tmp_path):
    scene = source("scenes", "robot_arm.json")
    simulated, recorded = tmp_path / "sim.csv", tmp_path / "rec.csv"
    subprocess.run([EXECUTABLE, "simulate", scene, "-o", simulated], check=True)
    subprocess.run([EXECUTABLE, "simulate", scene, "--integrator", "euler", "--step", "0.004", "-o", recorded],
                   check=True)
    page = view(tmp_path, scene, "--data", recorded, "--compare", simulated)
    at = probe(page, 1.5)
    assert len(at["ghosts"]) == len(at["bodies"]) == 7  # the arm's links
    apart = max(abs(gx - bx) + abs(gy - by) for (gx, gy), (bx, by) in zip(at["ghosts"], at["bodies"]))
    assert 0 < apart < 50, "the ghosts should follow the run closely, not sit on it"
    assert probe(view(tmp_path, scene), 1.5)["ghosts"] == []


@pytest.mark.parametrize("scene", sorted(glob.glob(source("scenes", "*.json"))), ids=os.path.basename)
def test_every_shipped_scene_plays_with_a_clean_console(tmp_path, scene):
    at = probe(view(tmp_path, scene), 0.3)  # probe asserts the clean console
    assert at["frames"] > 1 and len(at["bodies"]) > 0
