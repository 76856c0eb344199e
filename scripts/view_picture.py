"""The README's pictures of `tether view` and of a report, made in headless Chromium (network off): the robot arm's
page opened at t = 0.5 s (docs/figures/view_robot_arm.png) and the top of the README's arm identification report
(docs/figures/report_arm.png). Run from the repository with build/tether built."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TETHER = os.path.join(ROOT, "build", "tether")
FIGURES = os.path.join(ROOT, "docs", "figures")
ARM = os.path.join("docs", "examples", "arm")


def screenshot(page, picture, size):
    subprocess.run(["chromium-headless-shell", "--no-sandbox", "--use-angle=swiftshader",
                    "--enable-unsafe-swiftshader", f"--window-size={size}", "--virtual-time-budget=3000",
                    "--proxy-server=127.0.0.1:9", f"--screenshot={picture}", f"file://{page}"],
                   check=True, capture_output=True)
    print(f"wrote {os.path.relpath(picture, ROOT)}")


def main():
    with tempfile.TemporaryDirectory() as folder:
        page = os.path.join(folder, "arm.html")
        subprocess.run([TETHER, "view", os.path.join(ROOT, "scenes", "robot_arm.json"), "-o", page], check=True)
        screenshot(page + "#t=0.5", os.path.join(FIGURES, "view_robot_arm.png"), "900,560")
        report = os.path.join(folder, "report.html")
        subprocess.run([TETHER, "identify", os.path.join(ARM, "guess.json"), "--data", os.path.join(ARM, "encoders.csv"),
                        "--param", "/bodies/1/mass", "--param", "/bodies/1/inertia/1", "--param",
                        "/bodies/1/inertia/2", "--param", "/effects/1/damping", "--quiet", "--report", report],
                       check=True, capture_output=True, cwd=ROOT)  # the files named as the README names them
        screenshot(report, os.path.join(FIGURES, "report_arm.png"), "1100,1240")


if __name__ == "__main__":
    sys.exit(main())
