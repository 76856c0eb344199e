#!/usr/bin/env python3
"""Runs the gradient-cost benchmark (bench/gradient_bench.cc) and prints Markdown tables for the README.

    python3 bench/gradient_cost.py [--binary build/bench/tether_bench] [--min-time 0.2] [--repetitions 3]
                                   [--save out.json | --json saved.json] [extra benchmark flags]

One table per model (the 20- and 200-particle chains and the 7-link 3D arm): rows are the number of parameters
P; a cell gives the time of one gradient as a multiple of one plain double simulation of the same model and
observations (the benchmark's `x_plain_simulation` counter, both timed as thread CPU time in the same process)
and, in parentheses, the absolute CPU time of one gradient in ms; the adjoint's column also gives the memory it
kept (states and the largest record). With repetitions, every figure is the median over them (the ratio and the
time separately, so they need not divide exactly). Methods: Jets with the implicit-function KKT solve, Jets
factoring the Jet matrices (the test oracle, up to P = 32), central differences, the discrete adjoint. Below the
tables: per model, the cost of one Jet run (the median of multiple / ceil(P / 4) over P >= 4), the adjoint's
median multiple, and the crossover they imply, the smallest P with ceil(P / 4) Jet runs dearer than the adjoint
(gradient_method.h's kAdjointCrossover is the largest of them). The default settings take about 8 minutes on
two cores. Python 3 standard library only (with bench/bench_json.py, shared with studies/gradient_cost/run.py,
which draws these figures).
"""
import argparse
import math
import re
import statistics
import sys

import bench_json

METHODS = [("implicit", "Jet, implicit"), ("jet_factor", "Jet, factor Jets"), ("central", "central diff."),
           ("adjoint", "adjoint")]
NAME = re.compile(r"^(Gradient/(\w+)|PlainSimulation)/n:(\d+)/P:(\d+)$")
MIN_TIME, REPETITIONS = "0.2", 3  # the defaults: about 8 minutes on two cores
ARM = 7  # the benchmark's n for the 3D arm


def model_name(n):
    return "7-link 3D arm" if n == ARM else f"{n}-particle chain"


def run(binary, min_time=MIN_TIME, repetitions=REPETITIONS, extra=()):
    return bench_json.run(binary, "^(Gradient|PlainSimulation)/", min_time, repetitions, extra)


def parse(report):
    """The gradient benchmark's figures, as a dict: "cells" {(n, method, P): (multiple of a plain simulation,
    ms per gradient)}, "memory" {(n, P): adjoint MiB}, "plain" {n: ms per plain simulation}, "durations"
    {(n, method): simulated seconds}, "sizes" and "counts" (the models n and parameter counts P, sorted)."""
    cells, memory, plain, durations, sizes, counts = {}, {}, {}, {}, set(), set()
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
        if "memory_mb" in b:
            memory[(n, p)] = b["memory_mb"]
    return {"cells": cells, "memory": memory, "plain": plain, "durations": durations,
            "sizes": sorted(sizes, key=lambda n: (n == ARM, n)), "counts": sorted(counts)}


def crossover(parsed, n):
    """(one Jet run's multiple, the adjoint's median multiple, the smallest P at which the adjoint is cheaper)."""
    cells, counts = parsed["cells"], parsed["counts"]
    jet = [cells[(n, "implicit", p)][0] / math.ceil(p / 4) for p in counts if p >= 4 and (n, "implicit", p) in cells]
    adjoint = [cells[(n, "adjoint", p)][0] for p in counts if (n, "adjoint", p) in cells]
    if not jet or not adjoint:
        return None
    run, reverse = statistics.median(jet), statistics.median(adjoint)
    return run, reverse, 4 * math.floor(reverse / run) + 1


def milliseconds(value):
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def table(report):
    parsed = parse(report)
    cells, memory, plain, durations = parsed["cells"], parsed["memory"], parsed["plain"], parsed["durations"]
    out = []
    for n in parsed["sizes"]:
        spans = sorted({durations[k] for k in durations if k[0] == n})
        title = f"**{model_name(n)}**, " + ", ".join(f"{d:g}" for d in spans) + " s simulated"
        if n in plain:
            title += f"; one plain simulation takes {milliseconds(plain[n])} ms"
        header = ["P"] + [label for _, label in METHODS]
        lines = [title, "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        for p in parsed["counts"]:
            row = [str(p)]
            for method, _ in METHODS:
                cell = cells.get((n, method, p))
                text = "not run" if cell is None else f"{cell[0]:.1f}x ({milliseconds(cell[1])} ms)"
                if method == "adjoint" and (n, p) in memory:
                    text += f", {memory[(n, p)]:.2g} MiB"
                row.append(text)
            lines.append("| " + " | ".join(row) + " |")
        out.append("\n".join(lines))
    notes = []
    for n in parsed["sizes"]:
        c = crossover(parsed, n)
        if c:
            notes.append(f"{model_name(n)}: a Jet run costs {c[0]:.2f} plain simulations, the adjoint {c[1]:.1f}; "
                         f"the adjoint is the cheaper from P = {c[2]} on")
        largest = max(p for p in parsed["counts"] if (n, "adjoint", p) in parsed["cells"])
        adjoint = parsed["cells"][(n, "adjoint", largest)][0]
        jets = parsed["cells"].get((n, "implicit", largest))
        notes.append(f"{model_name(n)} at P = {largest}: the adjoint costs {adjoint:.2f} plain simulations"
                     + (f", {jets[0] / adjoint:.0f} times less than the Jets" if jets else ""))
    notes.append("a Jet gradient is ceil(P / 4) Jet runs; central differences are 1 + 2P plain runs; the adjoint "
                 "is one plain run and one recorded replay")
    notes.append("host: " + bench_json.host(report))
    return "\n\n".join(out) + "\n\n" + "\n".join(f"- {note}" for note in notes)


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
