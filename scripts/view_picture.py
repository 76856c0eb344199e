"""The README's picture of `tether view`: the robot arm's page opened at t = 0.5 s in headless Chromium (network
off), saved as docs/figures/view_robot_arm.png. Run from the repository with build/tether built."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TETHER = os.path.join(ROOT, "build", "tether")
PICTURE = os.path.join(ROOT, "docs", "figures", "view_robot_arm.png")


def main():
    with tempfile.TemporaryDirectory() as folder:
        page = os.path.join(folder, "arm.html")
        subprocess.run([TETHER, "view", os.path.join(ROOT, "scenes", "robot_arm.json"), "-o", page], check=True)
        subprocess.run(["chromium-headless-shell", "--no-sandbox", "--use-angle=swiftshader",
                        "--enable-unsafe-swiftshader", "--window-size=900,560", "--virtual-time-budget=3000",
                        "--proxy-server=127.0.0.1:9", f"--screenshot={PICTURE}", f"file://{page}#t=0.5"],
                       check=True, capture_output=True)
    print(f"wrote {os.path.relpath(PICTURE, ROOT)}")


if __name__ == "__main__":
    sys.exit(main())
