#!/usr/bin/env python3
"""Runs the gradient-cost benchmark (bench/gradient_bench.cc) and prints a Markdown table for the README.

    python3 bench/gradient_cost.py [--binary build/bench/tether_bench] [--min-time 0.2] [--repetitions 3]
                                   [--save out.json | --json saved.json] [extra benchmark flags]

Rows are the number of parameters P; for each chain size and method a cell gives the time of one gradient as a
multiple of one plain double simulation of the same model and observations (the benchmark's
`x_plain_simulation` counter, both timed as thread CPU time in the same process) and, in parentheses, the
absolute CPU time of one gradient in ms. With repetitions, every figure is the median over them (the ratio and
the time separately, so they need not divide exactly). Methods: Jets with the implicit-function KKT solve (the
default), Jets factoring the Jet matrices (the test oracle), central differences. The default settings take
about 2.5 minutes on two cores. Python 3 standard library only (with bench/bench_json.py, shared with
studies/gradient_cost/run.py, which draws these figures).
"""
import argparse
import re
import sys

import bench_json

METHODS = [("implicit", "Jet, implicit"), ("jet_factor", "Jet, factor Jets"), ("central", "central diff.")]
NAME = re.compile(r"^(Gradient/(\w+)|PlainSimulation)/n:(\d+)/P:(\d+)$")
MIN_TIME, REPETITIONS = "0.2", 3  # the defaults: about 2.5 minutes on two cores


def run(binary, min_time=MIN_TIME, repetitions=REPETITIONS, extra=()):
    return bench_json.run(binary, "^(Gradient|PlainSimulation)/", min_time, repetitions, extra)


def parse(report):
    """The gradient benchmark's figures, as a dict: "cells" {(n, method, P): (multiple of a plain simulation,
    ms per gradient)}, "plain" {n: ms per plain simulation}, "durations" {(n, method): simulated seconds},
    "sizes" and "counts" (the chain sizes n and parameter counts P, sorted)."""
    cells, plain, durations, sizes, counts = {}, {}, {}, set(), set()
    for b in bench_json.measurements(report):
        match = NAME.match(b["run_name"])
        if not match:
            continue
        method, n, p = match.group(2), int(match.group(3)), int(match.group(4))
        if method is None:
            plain[n] = b["plain_ms"]
            continue
        sizes.add(n)
        counts.add(p)
        durations[(n, method)] = b["duration_s"]
        cells[(n, method, p)] = (b["x_plain_simulation"], bench_json.cpu_milliseconds(b))
    return {"cells": cells, "plain": plain, "durations": durations, "sizes": sorted(sizes),
            "counts": sorted(counts)}


def milliseconds(value):
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def table(report):
    parsed = parse(report)
    cells, plain, durations, sizes = parsed["cells"], parsed["plain"], parsed["durations"], parsed["sizes"]
    header = ["P"] + [f"n={n} {label}" for n in sizes for _, label in METHODS]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for p in parsed["counts"]:
        row = [str(p)]
        for n in sizes:
            for method, _ in METHODS:
                cell = cells.get((n, method, p))
                row.append("not run" if cell is None else f"{cell[0]:.1f}x ({milliseconds(cell[1])} ms)")
        lines.append("| " + " | ".join(row) + " |")
    notes = []
    for n in sizes:
        spans = sorted({durations[k] for k in durations if k[0] == n})
        note = f"{n}-particle chain, " + ", ".join(f"{d:g}" for d in spans) + " s simulated"
        if n in plain:
            note += f": one plain simulation takes {milliseconds(plain[n])} ms"
        notes.append(note)
    notes.append("a Jet gradient is ceil(P / 4) Jet runs; central differences are 1 + 2P plain runs")
    notes.append("host: " + bench_json.host(report))
    return "\n".join(lines) + "\n\n" + "\n".join(f"- {note}" for note in notes)


def main(argv):
    parser = argparse.ArgumentParser(description="Runs the gradient-cost benchmark and prints a Markdown table.")
    parser.add_argument("--binary", default="build/bench/tether_bench", help="the tether_bench program")
    parser.add_argument("--min-time", default=MIN_TIME, help=f"--benchmark_min_time, seconds (default {MIN_TIME})")
    parser.add_argument("--repetitions", type=int, default=REPETITIONS,
                        help=f"--benchmark_repetitions (default {REPETITIONS})")
    parser.add_argument("--json", help="read this saved --benchmark_format=json output instead of running")
    parser.add_argument("--save", help="also write the benchmark's JSON output to this file")
    args, extra = parser.parse_known_args(argv)
    extra = [a for a in extra if a != "--"]
    if args.json:
        report = bench_json.load(args.json)
    else:
        report = run(args.binary, args.min_time, args.repetitions, extra)
        if args.save:
            bench_json.save(report, args.save)
    print(table(report))


if __name__ == "__main__":
    main(sys.argv[1:])
