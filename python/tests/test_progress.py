"""A long identify, fit or tune shows its progress on stderr when stderr is a terminal (a line redrawn in place,
erased at the end), never with --quiet, and a short run in a pipe prints none."""
import os
import subprocess

from conftest import EXECUTABLE, source

# about 2 s: a derivative-free optimizer on the README's identification at a tenth of its step
SLOW = [EXECUTABLE, "identify", source("docs", "examples", "identify", "guess.json"), "--data",
        source("docs", "examples", "identify", "recording.csv"), "--param", "/bodies/1/mass",
        "--optimizer", "nlopt:LN_SBPLX", "--max-evaluations", "60", "--step", "1e-4"]


def stderr_on_a_terminal(command):
    master, slave = os.openpty()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    text = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the other end closed
            break
        if not chunk:
            break
        text += chunk
    os.close(master)
    process.wait()
    return text.decode()


def test_a_long_identification_shows_its_progress_on_a_terminal_and_erases_it():
    text = stderr_on_a_terminal(SLOW)
    assert "\rtether: identify: " in text and " evaluations, smallest cost " in text
    progress_end = text.rindex("\r\x1b[K")  # erased before the warnings and the results
    assert "smallest cost" not in text[progress_end:]


def test_quiet_and_pipes_show_no_progress():
    assert "smallest cost" not in stderr_on_a_terminal(SLOW + ["--quiet"])
    piped = subprocess.run(SLOW, capture_output=True, text=True)  # a log gets a line from 10 s on only
    assert "smallest cost" not in piped.stderr
