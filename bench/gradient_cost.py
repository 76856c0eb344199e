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
about 2.5 minutes on two cores. Python 3 standard library only.
"""
import argparse
import json
import re
import subprocess
import sys

METHODS = [("implicit", "Jet, implicit"), ("jet_factor", "Jet, factor Jets"), ("central", "central diff.")]
NAME = re.compile(r"^(Gradient/(\w+)|PlainSimulation)/n:(\d+)/P:(\d+)(_median)?$")


def run(binary, min_time, repetitions, extra):
    command = [binary, "--benchmark_filter=^(Gradient|PlainSimulation)/", "--benchmark_format=json",
               f"--benchmark_min_time={min_time}", f"--benchmark_repetitions={repetitions}"] + extra
    print("running: " + " ".join(command), file=sys.stderr)
    done = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True)
    return json.loads(done.stdout)


def milliseconds(value):
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def table(report):
    cells, plain, durations, sizes, counts = {}, {}, {}, set(), set()
    # with --benchmark_repetitions, the medians of the repetitions; otherwise the single runs
    medians = any(b.get("aggregate_name") == "median" for b in report["benchmarks"])
    for b in report["benchmarks"]:
        wanted = b.get("aggregate_name") == "median" if medians else b.get("run_type", "iteration") == "iteration"
        if not wanted or b.get("error_occurred"):
            continue
        match = NAME.match(b["name"])
        if not match:
            continue
        method, n, p = match.group(2), int(match.group(3)), int(match.group(4))
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
        if method is None:
            plain[n] = b["plain_ms"]
            continue
        sizes.add(n)
        counts.add(p)
        durations[(n, method)] = b["duration_s"]
        cells[(n, method, p)] = (b["x_plain_simulation"], b["cpu_time"] * scale)
    sizes, counts = sorted(sizes), sorted(counts)
    header = ["P"] + [f"n={n} {label}" for n in sizes for _, label in METHODS]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for p in counts:
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
    context = report.get("context", {})
    notes.append(f"host: {context.get('num_cpus', '?')} CPUs at {context.get('mhz_per_cpu', '?')} MHz, "
                 f"load average {context.get('load_avg', '?')}, {context.get('date', '')}")
    return "\n".join(lines) + "\n\n" + "\n".join(f"- {note}" for note in notes)


def main(argv):
    parser = argparse.ArgumentParser(description="Runs the gradient-cost benchmark and prints a Markdown table.")
    parser.add_argument("--binary", default="build/bench/tether_bench", help="the tether_bench program")
    parser.add_argument("--min-time", default="0.2", help="--benchmark_min_time, seconds (default 0.2)")
    parser.add_argument("--repetitions", type=int, default=3, help="--benchmark_repetitions (default 3)")
    parser.add_argument("--json", help="read this saved --benchmark_format=json output instead of running")
    parser.add_argument("--save", help="also write the benchmark's JSON output to this file")
    args, extra = parser.parse_known_args(argv)
    extra = [a for a in extra if a != "--"]
    if args.json:
        with open(args.json) as f:
            report = json.load(f)
    else:
        report = run(args.binary, args.min_time, args.repetitions, extra)
        if args.save:
            with open(args.save, "w") as f:
                json.dump(report, f, indent=1)
    print(table(report))


if __name__ == "__main__":
    main(sys.argv[1:])
