#!/usr/bin/env python3
"""Fails when the READMEs and the deterministic scripts that produce their numbers disagree (timings excepted).

    python3 scripts/check_readme_numbers.py [--tether build/tether]

- README.md's tuning table against `bench/tune_table.py` (every column but the tuning time);
- README.md's accuracy table of the shipped pendulum against `bench/pendulum_accuracy.py`;
- the stability-map count in README.md and studies/README.md against `studies/stability_maps/check_bound.py`;
- the accuracy study's readings in README.md and studies/README.md against `studies/accuracy/readings.py`
  (the committed results.csv of each study: regenerating a study means running it, then this check).
Every number a script prints (two or more characters, or with a decimal point or exponent) must appear in the
README it is quoted in. Exit status 1 with the disagreements listed, 0 when all agree. Standard library only.
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def text(name):
    with open(os.path.join(ROOT, name)) as f:
        return f.read()


def output(*command):
    return subprocess.run([sys.executable, *command], capture_output=True, text=True, check=True, cwd=ROOT).stdout


def numbers(line):
    return [n for n in re.findall(r"\d+(?:\.\d+)?(?:e[+-]?\d+)?", line) if len(n) > 1 or "." in n]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
    args = parser.parse_args()
    problems = []

    readme = text("README.md")
    table = [line for line in output("bench/tune_table.py", "--tether", args.tether).splitlines() if line.startswith("| ")]
    for line in table[1:]:  # the header row, then the scenes (the separator does not start with "| ")
        key = line.rsplit("|", 2)[0]  # without the tuning time
        if key not in readme:
            problems.append("README.md's tuning table lacks the row " + key + "|")

    accuracy = output("bench/pendulum_accuracy.py", "--tether", args.tether).splitlines()
    for line in [line for line in accuracy if line.startswith("| ")][1:]:  # the pendulum's accuracy table
        if line not in readme:
            problems.append("README.md's pendulum accuracy table lacks the row " + line)

    for script, readmes in (("studies/stability_maps/check_bound.py", ("README.md", "studies/README.md")),
                            ("studies/accuracy/readings.py", ("README.md", "studies/README.md"))):
        for line in output(script).splitlines():
            if line.startswith("disagrees:"):
                continue  # listed for the reader; its numbers are quoted in prose
            if line.startswith("timings:"):
                continue  # wall times, which change from run to run
            for name in readmes:
                missing = [n for n in numbers(line) if n not in text(name)]
                if missing:
                    problems.append("%s does not quote %s from %s: '%s'" % (name, ", ".join(missing), script, line))

    for problem in problems:
        print("check_readme_numbers: " + problem)
    if not problems:
        print("check_readme_numbers: the READMEs agree with bench/tune_table.py, pendulum_accuracy.py, check_bound.py and readings.py")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
