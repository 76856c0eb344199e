"""Runs tether_bench with --benchmark_format=json and picks its measurements; shared by bench/gradient_cost.py
and the studies that draw benchmark figures (studies/gradient_cost, studies/scaling). Standard library only.
"""
import argparse
import json
import os
import subprocess
import sys

DEFAULT_BINARY = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "build", "bench",
                              "tether_bench")

# google benchmark's time units, in milliseconds
MILLISECONDS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def run(binary, pattern, min_time, repetitions, extra=(), interleave=True):
    """Runs the benchmarks whose names match the regular expression `pattern`; returns the parsed JSON report.
    With `interleave`, repetitions run in a random order across the whole run (Google Benchmark's random
    interleaving): back to back, the repetitions of one case shared the same burst of load from the machine's
    neighbours, and their median with them (tether's 10-rod chain, rk4, in bench/peer once read 55, 80 and 92 ms in
    a row, MuJoCo's 76, 68 and 68 ms after them: a median of 1.18 times MuJoCo's step from a scene that steps in 0.83
    of it). Without it they run back to back, each after the one before has warmed the caches: for runs of a
    millisecond or less that include their set-up (bench/peer/simbody_bench.cc), which interleaving made up to
    twice as long."""
    if not os.path.exists(binary):
        sys.exit(f"{binary} not found: build it (scripts/dev run builds build/bench/tether_bench) or pass --binary")
    command = [binary, f"--benchmark_filter={pattern}", "--benchmark_format=json",
               f"--benchmark_min_time={min_time}", f"--benchmark_repetitions={repetitions}"] + list(extra)
    if interleave and repetitions > 1:
        command.append("--benchmark_enable_random_interleaving=true")
    print("running: " + " ".join(command), file=sys.stderr)
    done = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True)
    return json.loads(done.stdout)


def load(path):
    with open(path) as f:
        return json.load(f)


def save(report, path):
    with open(path, "w") as f:
        json.dump(report, f, indent=1)
        f.write("\n")


def measurements(report):
    """The report's benchmarks worth reading, each once: with --benchmark_repetitions, the medians of the
    repetitions; otherwise the single runs. Runs that reported an error are left out. Each entry's "run_name"
    is the benchmark's name without the aggregate suffix. They come in the order the benchmarks were registered (a
    run with random interleaving reports them in the order their last repetitions ended)."""
    medians = any(b.get("aggregate_name") == "median" for b in report["benchmarks"])
    picked = []
    for b in report["benchmarks"]:
        wanted = b.get("aggregate_name") == "median" if medians else b.get("run_type", "iteration") == "iteration"
        if wanted and not b.get("error_occurred"):
            name = b.get("run_name", b["name"])
            if name.endswith("_median"):
                name = name[: -len("_median")]
            picked.append(dict(b, run_name=name))
    return sorted(picked, key=lambda b: (b.get("family_index", 0), b.get("per_family_instance_index", 0)))


def cpu_milliseconds(entry):
    """The entry's CPU time per iteration, in milliseconds."""
    return entry["cpu_time"] * MILLISECONDS[entry.get("time_unit", "ns")]


def host(report):
    """One line on the machine and its load while the benchmark ran."""
    context = report.get("context", {})
    return (f"{context.get('num_cpus', '?')} CPUs at {context.get('mhz_per_cpu', '?')} MHz, "
            f"load average {context.get('load_avg', '?')}, {context.get('date', '')}")


def study_report(argv, description, out, min_time, repetitions, run_benchmarks):
    """The command line of a study drawn from benchmarks: --binary, --min-time, --repetitions, --json, --out.
    Returns (report, out folder): the report saved earlier when --json names it, else a fresh
    run_benchmarks(binary, min_time, repetitions, extra flags), saved as OUT/results.json."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--binary", default=DEFAULT_BINARY,
                        help="the tether_bench program (default: build/bench/tether_bench)")
    parser.add_argument("--min-time", default=min_time, help=f"--benchmark_min_time, seconds (default {min_time})")
    parser.add_argument("--repetitions", type=int, default=repetitions,
                        help=f"--benchmark_repetitions, figures are the medians (default {repetitions})")
    parser.add_argument("--json", help="redraw from this saved results.json instead of running the benchmark")
    parser.add_argument("--out", default=out, help="folder for results.json and the figures (default: the study's)")
    args, extra = parser.parse_known_args(argv)
    if args.json:
        return load(args.json), args.out
    report = run_benchmarks(args.binary, args.min_time, args.repetitions, [a for a in extra if a != "--"])
    save(report, os.path.join(args.out, "results.json"))
    return report, args.out


def peer_report(argv, description, binary, program, out, interleave=True):
    """The command line of a side-by-side comparison (bench/peer): --binary, --json, --out, --filter. Returns the
    report saved earlier when --json names it, else a fresh run (three repetitions, interleaved or not as run()
    says) saved as --out; the runs that failed are named on stderr."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--binary", default=binary, help=f"the {program} program")
    parser.add_argument("--json", help="print this saved report instead of running the benchmark")
    parser.add_argument("--out", default=out, help="where to save the report")
    parser.add_argument("--filter", default=".", help="--benchmark_filter (default: every scene)")
    args = parser.parse_args(argv)
    if args.json:
        report = load(args.json)
    else:
        report = run(args.binary, args.filter, 0, 3, interleave=interleave)
        save(report, args.out)
        print(f"wrote {args.out}", file=sys.stderr)
    for entry in report["benchmarks"]:
        if entry.get("error_occurred") and entry.get("run_type") != "aggregate":
            print(f"{entry['run_name']} failed: {entry.get('error_message')}", file=sys.stderr)
    return report


def save_figure(figure, report, out, name, dpi):
    """Signs the figure with the benchmark's host and writes out/name.png and .svg (the SVG without a date, so
    that a redraw changes nothing)."""
    figure.text(0.99, 0.01, "host: " + host(report), fontsize=6, color="0.5", ha="right")
    figure.tight_layout(rect=(0, 0.02, 1, 1))
    for extension in ("png", "svg"):
        path = os.path.join(out, name + "." + extension)
        figure.savefig(path, dpi=dpi, metadata={"Date": None} if extension == "svg" else {})
        print("wrote " + path, file=sys.stderr)


def pyplot():
    """matplotlib.pyplot for files (the Agg backend), with a fixed SVG hash salt so that the same numbers give the
    same SVG; exits with a hint when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        sys.exit("run.py: drawing needs matplotlib (Debian: apt-get install python3-matplotlib)")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams["svg.hashsalt"] = "tether"
    return plt
