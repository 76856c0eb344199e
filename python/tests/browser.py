"""Opening tether's pages (tether view, reports, a study's index) in Debian's headless Chromium with the network off,
for the browser tests. Without the browser they fail: the README's test command installs chromium-headless-shell."""
import json
import re
import shutil
import subprocess

import matplotlib.image

BROWSER = "chromium-headless-shell"
WIDTH, HEIGHT = 900, 600
BACKGROUND = [0xF4 / 255, 0xF4 / 255, 0xF4 / 255]  # the viewer's


def browse(page, fragment, *how, size=(WIDTH, HEIGHT)):
    """Opens file://PAGE FRAGMENT; returns (stdout, the console's lines)."""
    assert shutil.which(BROWSER), f"{BROWSER} is missing: apt-get install chromium-headless-shell (scripts/dev does)"
    done = subprocess.run(
        [BROWSER, "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=3000", "--enable-logging=stderr", "--v=0",
         "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>", "--host-resolver-rules=MAP * ~NOTFOUND",
         *how, f"file://{page}{fragment}"],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    console = [line for line in done.stderr.splitlines() if ":CONSOLE(" in line]
    return done.stdout, console


def dom_of(page, fragment=""):
    """The page's DOM once its scripts ran; its console must stay empty."""
    dom, console = browse(page, fragment, "--dump-dom")
    assert console == [], console
    return dom


def page_probe(page, probe_id, fragment=""):
    """The JSON a page writes into its hidden <pre id=PROBE_ID> once drawn."""
    found = re.search(rf'<pre id="{probe_id}" hidden="">(.*?)</pre>', dom_of(page, fragment), re.S)
    assert found, "the page wrote no probe: its script did not run"
    return json.loads(found.group(1).replace("&quot;", '"'))


def browser_screenshot(page, fragment, shot, size=(WIDTH, HEIGHT)):
    """The page as shown (RGB, 0..1)."""
    _, console = browse(page, fragment, f"--screenshot={shot}", size=size)
    assert console == [], console
    return matplotlib.image.imread(shot)[:, :, :3]
