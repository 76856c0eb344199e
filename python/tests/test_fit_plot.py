"""`tether fit --plot` labels every axis with its unit and draws the schedule the fit set, through its knots."""
import subprocess

from conftest import EXECUTABLE, source


def test_the_swing_up_plot_has_units_and_the_fitted_torque(tmp_path):
    plot = tmp_path / "swing_up.svg"
    done = subprocess.run([EXECUTABLE, "fit", source("docs", "examples", "swing_up", "pendulum.json"),
                           "--param", "/effects/1/schedule/values/*", "--bound", "/effects/1/schedule/values/*=-2:2",
                           "--effort", "0.1", "--at-least", "axle.angle=3@3", "--at-most", "axle.angle=3.3@3",
                           "--starts", "2", "--plot", str(plot)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    text = plot.read_text()
    for label in ("axle.angle (rad)", "motor on axle (N m)", "fitted knots", "t (s)"):
        assert label in text, label
