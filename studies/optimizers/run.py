#!/usr/bin/env python3
"""The optimizers study (issue 6): Ceres and NLopt algorithms on tether's tuning and identification problems.

    /usr/bin/python3 studies/optimizers/run.py [--tether build/tether]

Drives the command-line tool only (`tether tune`, `tether identify`, `tether simulate`), one run at a time so that
wall times are comparable, with the same budget (--max-evaluations) for every optimizer, and writes into
studies/optimizers/results/:

- results.csv: one row per run (problem, optimizer, start, repeat, status, evaluations, seconds, objective,
  objective / best, success, estimates, message);
- objective_vs_time.png and .svg: final objective relative to the best found for the problem against the
  optimizer's wall time, one panel per problem;
- summary.md: success matrix, per-problem table (median evaluations, median time, best and median objective,
  success rate), timing spread between repeats, the machine; the same text replaces the generated block of
  studies/optimizers/README.md;
- damped_recording.csv: the recording of the third identification problem (made here from
  damped_double_pendulum.json with seeded noise).

Success rule: a run succeeds when tether exits 0 and its final objective is at most (1 + 1e-2) times the best
objective found for that problem by any optimizer from any start. Standard library and matplotlib only.
"""
import argparse, csv, json, math, os, platform, random, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
RESULTS = os.path.join(HERE, "results")
sys.path.insert(0, os.path.join(ROOT, "studies"))
import index_page  # noqa: E402
EXAMPLE = os.path.join(ROOT, "docs", "examples", "identify")

BUDGET = 100            # --max-evaluations for every run
SUCCESS_TOLERANCE = 1e-2  # success: objective <= (1 + SUCCESS_TOLERANCE) * best for the problem
OPTIMIZERS = ["ceres", "nlopt:LD_LBFGS", "nlopt:LD_SLSQP", "nlopt:LD_MMA", "nlopt:LN_BOBYQA", "nlopt:LN_COBYLA",
              "nlopt:LN_NELDERMEAD", "nlopt:LN_SBPLX", "nlopt:GN_DIRECT_L", "nlopt:GN_CRS2_LM"]

# Tuning problems: `tether tune` starts from the best critically damped preset inside its box (chosen by the tool,
# no option sets it), so each problem has one start; it is repeated to measure the timing spread.
TUNE_PROBLEMS = [
    ("tune pendulum rk4 h=1e-2", "scenes/pendulum.json", ["--step", "1e-2"]),
    ("tune double_pendulum rk4 h=1e-2", "scenes/double_pendulum.json", ["--step", "1e-2"]),
    ("tune double_pendulum rk4 h=1e-3", "scenes/double_pendulum.json", []),
    ("tune four_bar rk4 h=1e-2", "scenes/four_bar.json", ["--step", "1e-2"]),
    ("tune four_bar rk4 h=1e-3", "scenes/four_bar.json", []),
    ("tune four_bar symplectic_euler h=1e-3", "scenes/four_bar.json", ["--integrator", "symplectic_euler"]),
]

# Identification problems: starts are the base scene with every unknown scaled by a factor drawn log-uniformly
# in [0.5, 2] (seeded by problem and start index, the same for every optimizer).
IDENTIFY_PROBLEMS = [
    {"name": "identify example mass, 6 segments",
     "base": os.path.join(EXAMPLE, "guess.json"), "data": os.path.join(EXAMPLE, "recording.csv"),
     "params": {"/bodies/1/mass": (0.5, 4.0)}, "extra": ["--segments", "6"], "global_ok": False},
    {"name": "identify example mass, single shooting",
     "base": os.path.join(EXAMPLE, "guess.json"), "data": os.path.join(EXAMPLE, "recording.csv"),
     "params": {"/bodies/1/mass": (0.5, 4.0)}, "extra": [], "global_ok": True},
    {"name": "identify damped pendulum m1, c, g",
     "base": os.path.join(HERE, "damped_double_pendulum.json"), "data": os.path.join(RESULTS, "damped_recording.csv"),
     "params": {"/bodies/1/mass": (0.3, 6.0), "/effects/1/coefficient": (0.05, 3.0),
                "/effects/0/acceleration/1": (-30.0, -3.0)},
     "extra": ["--integrator", "rk4", "--step", "2e-3"], "global_ok": True},
]

FIELDS = ["problem", "kind", "optimizer", "start", "repeat", "status", "exit_code", "evaluations", "seconds",
          "wall_seconds", "initial_objective", "objective", "relative", "success", "estimate", "message"]


def pointer_set(doc, pointer, value):
    parts = [p.replace("~1", "/").replace("~0", "~") for p in pointer.split("/")[1:]]
    for p in parts[:-1]:
        doc = doc[int(p)] if isinstance(doc, list) else doc[p]
    if isinstance(doc, list):
        doc[int(parts[-1])] = value
    else:
        doc[parts[-1]] = value


def pointer_get(doc, pointer):
    for p in [p.replace("~1", "/").replace("~0", "~") for p in pointer.split("/")[1:]]:
        doc = doc[int(p)] if isinstance(doc, list) else doc[p]
    return doc


def run_tether(tether, args):
    """Runs tether; returns (exit code, parsed JSON or None, message, wall seconds)."""
    begin = time.perf_counter()
    try:
        out = subprocess.run([tether] + args, capture_output=True, text=True, timeout=300)
    except subprocess.TimeoutExpired:
        return -1, None, "timed out after 300 s", time.perf_counter() - begin
    except OSError as e:  # not an optimizer failure: the binary is missing or being rebuilt
        sys.exit(f"run.py: cannot run {tether}: {e}")
    wall = time.perf_counter() - begin
    errors = [line for line in out.stderr.splitlines() if line.startswith("tether: error")]
    if out.returncode != 0:
        return out.returncode, None, (errors[-1] if errors else out.stderr.strip()[-300:]), wall
    try:
        return 0, json.loads(out.stdout), "", wall
    except json.JSONDecodeError as e:
        return 0, None, f"unreadable JSON on stdout: {e}", wall


def make_recording(tether):
    """damped_recording.csv: the truth scene by rk45 at h = 1e-3, every 20 ms, 1 mm Gaussian noise (seed 1)."""
    with tempfile.TemporaryDirectory() as work:
        truth_csv = os.path.join(work, "truth.csv")
        subprocess.run([tether, "simulate", os.path.join(HERE, "damped_double_pendulum.json"), "--every", "20",
                        "-o", truth_csv], check=True)
        rows = list(csv.DictReader(open(truth_csv)))
    rng = random.Random(1)
    columns = ["p0.x", "p0.y", "p1.x", "p1.y"]
    with open(os.path.join(RESULTS, "damped_recording.csv"), "w") as f:
        f.write(",".join(["t"] + columns) + "\n")
        for r in rows:
            f.write(",".join([r["t"]] + ["%.6f" % (float(r[c]) + rng.gauss(0.0, 1e-3)) for c in columns]) + "\n")


def row(problem, kind, optimizer, start, repeat, code, result, message, wall):
    r = {"problem": problem, "kind": kind, "optimizer": optimizer, "start": start, "repeat": repeat,
         "exit_code": code, "wall_seconds": wall, "message": message, "status": "ok" if result else "error"}
    if result:
        r["evaluations"] = result["evaluations"]
        r["seconds"] = result["seconds"]
        r["message"] = result.get("optimizer_message", "")
        if kind == "tune":
            r["objective"] = result["objective"]
            r["estimate"] = json.dumps({"alpha": result["alpha"], "beta": result["beta"]})
        else:
            r["objective"] = result["final_cost"]
            r["initial_objective"] = result["initial_cost"]
            r["estimate"] = json.dumps(result["parameters"])
        if r["objective"] is None:  # NaN prints as null
            r["status"] = "error"
            r["message"] = "exit 0 but the objective is null (NaN); optimizer message: " + r["message"]
            r["objective"] = ""
    return r


def progress(i, total, began, text):
    elapsed = time.time() - began
    print(f"[{i}/{total} {elapsed:5.0f} s] {text}", file=sys.stderr, flush=True)


def run_all(tether, repeats, starts):
    runs = []  # (description, function returning a row)
    for name, scene, extra in TUNE_PROBLEMS:
        for repeat in range(repeats):
            for opt in OPTIMIZERS:
                args = ["tune", os.path.join(ROOT, scene), *extra, "--optimizer", opt, "--max-evaluations", str(BUDGET)]
                runs.append((f"{name} {opt} repeat {repeat}",
                             lambda a=args, n=name, o=opt, k=repeat: row(n, "tune", o, "tool", k, *run_tether(tether, a))))
    work = tempfile.TemporaryDirectory()
    for p in IDENTIFY_PROBLEMS:
        base = json.load(open(p["base"]))
        scenes = []
        for s in range(starts):
            rng = random.Random(f"{p['name']} start {s}")
            scene = json.loads(json.dumps(base))
            for ptr in p["params"]:
                pointer_set(scene, ptr, pointer_get(base, ptr) * math.exp(rng.uniform(math.log(0.5), math.log(2.0))))
            path = os.path.join(work.name, f"{len(runs)}_start{s}.json")
            json.dump(scene, open(path, "w"), indent=1)
            scenes.append(path)
        for opt in OPTIMIZERS:
            not_applicable = opt.startswith("nlopt:G") and not p["global_ok"]
            for s, path in enumerate(scenes[:1] if not_applicable else scenes):
                args = ["identify", path, "--data", p["data"], *p["extra"], "--optimizer", opt,
                        "--max-evaluations", str(BUDGET)]
                for ptr, (lo, hi) in p["params"].items():
                    args += ["--param", ptr, "--bound", f"{ptr}={lo}:{hi}"]

                def one(a=args, n=p["name"], o=opt, k=s, na=not_applicable):
                    r = row(n, "identify", o, k, 0, *run_tether(tether, a))
                    if na:
                        r["status"] = "n/a"
                    return r
                runs.append((f"{p['name']} {opt} start {s}", one))
    rows, began = [], time.time()
    for i, (text, fn) in enumerate(runs):
        progress(i + 1, len(runs), began, text)
        rows.append(fn())
    work.cleanup()
    return rows


def judge(rows):
    best = {}
    for r in rows:
        if r["status"] == "ok" and math.isfinite(r["objective"]):
            best[r["problem"]] = min(best.get(r["problem"], math.inf), r["objective"])
    for r in rows:
        if r["status"] == "ok":
            r["relative"] = r["objective"] / best[r["problem"]] if best[r["problem"]] > 0 else 1.0
            r["success"] = int(r["relative"] <= 1.0 + SUCCESS_TOLERANCE)
        elif r["status"] == "error":
            r["success"] = 0
    return best


def fmt(x, digits=3):
    return "" if x is None or x == "" else f"{x:.{digits}g}"


def machine():
    model = "unknown"
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} CPUs ({platform.system()} {platform.release()})"


def summarize(rows, best, info):
    problems = [p[0] for p in TUNE_PROBLEMS] + [p["name"] for p in IDENTIFY_PROBLEMS]
    short = {n: n.replace("tune ", "").replace("identify ", "") for n in problems}
    lines = ["### Success matrix", "",
             f"Successful runs / runs (success: exit 0 and final objective <= (1 + {SUCCESS_TOLERANCE:g}) x the best "
             "found for the problem by any optimizer; n/a: a global NLopt algorithm needs single shooting). Tuning: "
             "one start chosen by the tool, run "
             f"{info['repeats']} times; identification: {info['starts']} starts.", ""]
    lines.append("| optimizer | " + " | ".join(short[n] for n in problems) + " | tuning | identification |")
    lines.append("|---" * (len(problems) + 3) + "|")
    for opt in OPTIMIZERS:
        cells, totals = [], {"tune": [0, 0], "identify": [0, 0]}
        for n in problems:
            sel = [r for r in rows if r["problem"] == n and r["optimizer"] == opt]
            if sel and all(r["status"] == "n/a" for r in sel):
                cells.append("n/a")
                continue
            ok = sum(r["success"] for r in sel)
            cells.append(f"{ok}/{len(sel)}")
            totals[sel[0]["kind"]][0] += ok
            totals[sel[0]["kind"]][1] += len(sel)
        tot = [f"{a}/{b} ({100 * a / b:.0f}%)" if b else "n/a" for a, b in totals.values()]
        lines.append(f"| {opt} | " + " | ".join(cells) + " | " + " | ".join(tot) + " |")
    lines += ["", "### Per problem", "",
              "Evaluations and seconds as tether reports them (`evaluations`, `seconds`: the optimization itself; "
              "tuning's reference motion is computed before and not included). Objective: `objective` (m) for tune, "
              "`final_cost` for identify.", "",
              "| problem | optimizer | runs | success | median evaluations | median s | best objective | "
              "median objective | median objective / best | within 10% of best |", "|---|---|---|---|---|---|---|---|---|---|"]
    for n in problems:
        for opt in OPTIMIZERS:
            sel = [r for r in rows if r["problem"] == n and r["optimizer"] == opt]
            if all(r["status"] == "n/a" for r in sel):
                lines.append(f"| {short[n]} | {opt} | n/a | | | | | | | |")
                continue
            ok = [r for r in sel if r["status"] == "ok"]
            errors = len(sel) - len(ok)
            rate = f"{100 * sum(r['success'] for r in sel) / len(sel):.0f}%" + (f" ({errors} errors)" if errors else "")
            if ok:
                ev = statistics.median(r["evaluations"] for r in ok)
                sec = statistics.median(r["seconds"] for r in ok)
                objs = [r["objective"] for r in ok]
                loose = sum(r["relative"] <= 1.1 for r in ok)
                lines.append(f"| {short[n]} | {opt} | {len(sel)} | {rate} | {ev:g} | {sec:.3g} | {min(objs):.4g} | "
                             f"{statistics.median(objs):.4g} | {statistics.median(objs) / best[n]:.4g} | "
                             f"{loose}/{len(sel)} |")
            else:
                lines.append(f"| {short[n]} | {opt} | {len(sel)} | {rate} | | | | | | 0/{len(sel)} |")
    lines += ["", "Best objective per problem: " + "; ".join(f"{short[n]}: {best[n]:.4g}" for n in problems), ""]
    # timing spread: identical tuning runs repeated
    spreads = []
    for n, _, _ in TUNE_PROBLEMS:
        for opt in OPTIMIZERS:
            t = [r["seconds"] for r in rows if r["problem"] == n and r["optimizer"] == opt and r["status"] == "ok"]
            if len(t) > 1 and min(t) > 0:
                spreads.append((max(t) / min(t), n, opt))
    differing = sorted({o for n, _, _ in TUNE_PROBLEMS for o in OPTIMIZERS
                        if len({r["objective"] for r in rows if r["problem"] == n and r["optimizer"] == o
                                and r["status"] == "ok"}) > 1})
    lines += ["### Timing spread", ""]
    if spreads:
        ratios = sorted(s[0] for s in spreads)
        worst = max(spreads)
        lines.append(f"Each tuning run was repeated {info['repeats']} times, one run at a time. Slowest / fastest "
                     f"repeat of the same run: median {statistics.median(ratios):.2f}, 90th percentile "
                     f"{ratios[int(0.9 * (len(ratios) - 1))]:.2f}, largest {worst[0]:.2f} ({worst[2]} on "
                     f"{short[worst[1]]}). Repeats gave identical objectives"
                     + (f" except for {', '.join(differing)} (randomized, and tether does not seed NLopt's generator)."
                        if differing else "."))
    lines += ["", "### Machine", "",
              f"{info['machine']}; load average {info['load_before']} before the run and {info['load_after']} after; "
              f"the whole study took {info['total']:.0f} s of wall time ({len(rows)} tether runs, "
              f"{info['date']}).", ""]
    return "\n".join(lines)


def plot(rows, best):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    problems = [p[0] for p in TUNE_PROBLEMS] + [p["name"] for p in IDENTIFY_PROBLEMS]
    colors = plt.get_cmap("tab10").colors
    markers = ["o", "s", "D", "^", "v", "<", ">", "P", "X", "*"]
    style = {opt: (colors[i % 10], markers[i % len(markers)]) for i, opt in enumerate(OPTIMIZERS)}
    fig, axes = plt.subplots(3, 3, figsize=(15, 12.5))
    for ax, n in zip(axes.flat, problems):
        sel = [r for r in rows if r["problem"] == n]
        ok = [r for r in sel if r["status"] == "ok"]
        top = max([r["relative"] for r in ok] + [10.0]) * 3
        for opt in OPTIMIZERS:
            pts = [r for r in ok if r["optimizer"] == opt]
            c, m = style[opt]
            ax.scatter([max(r["seconds"], 1e-3) for r in pts], [r["relative"] for r in pts], color=c, marker=m,
                       s=36, alpha=0.75, edgecolors="none", label=opt)
            err = [r for r in sel if r["optimizer"] == opt and r["status"] == "error"]
            if err:  # error exits: drawn at the top of the panel at their wall time
                ax.scatter([r["wall_seconds"] for r in err], [top / 1.5] * len(err), color=c, marker=m, s=60,
                           facecolors="none")
        ax.axhline(1.0 + SUCCESS_TOLERANCE, color="grey", lw=0.8, ls="--")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(0.8, top)
        ax.set_title(f"{n}\nbest objective {best[n]:.3g}", fontsize=10)
        ax.set_xlabel("optimizer wall time (s)")
        ax.set_ylabel("final objective / best")
        ax.xaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(True, which="major", alpha=0.3)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=10, frameon=False)
    fig.suptitle(f"Optimizers on tether's problems: final objective relative to the best found vs time "
                 f"(budget {BUDGET} evaluations)\n"
                 f"dashed: success threshold, 1 + {SUCCESS_TOLERANCE:g}; hollow markers at the top: runs without a "
                 "usable objective (error exit, or a NaN objective), at their process wall time", fontsize=12)
    fig.tight_layout(rect=(0, 0.06, 1, 0.95))
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(RESULTS, f"objective_vs_time.{ext}"), dpi=110)


def update_readme(text):
    path = os.path.join(HERE, "README.md")
    begin, end = "<!-- generated by run.py: begin -->", "<!-- generated by run.py: end -->"
    if not os.path.exists(path):
        return
    readme = open(path).read()
    if begin in readme and end in readme:
        head, rest = readme.split(begin, 1)
        tail = rest.split(end, 1)[1]
        open(path, "w").write(head + begin + "\n" + text + "\n" + end + tail)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tether", default=os.path.join(ROOT, "build", "tether"))
    ap.add_argument("--repeats", type=int, default=2, help="repeats of every tuning run (timing spread)")
    ap.add_argument("--starts", type=int, default=8, help="starts per identification problem")
    ap.add_argument("--replot", action="store_true",
                    help="redo summary, README block and figure from results/results.csv without running tether")
    args = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    if args.replot:
        rows = load_rows()
        best = judge(rows)
        info = json.load(open(os.path.join(RESULTS, "run_info.json")))
        finish(rows, best, info)
        return
    began = time.time()
    info = {"repeats": args.repeats, "starts": args.starts, "machine": machine(),
            "load_before": " ".join(f"{x:.2f}" for x in os.getloadavg()),
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    make_recording(args.tether)
    rows = run_all(args.tether, args.repeats, args.starts)
    best = judge(rows)
    info["total"] = time.time() - began
    info["load_after"] = " ".join(f"{x:.2f}" for x in os.getloadavg())
    json.dump(info, open(os.path.join(RESULTS, "run_info.json"), "w"), indent=1)
    with open(os.path.join(RESULTS, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r.get(k), float) and k in ("seconds", "wall_seconds")
                            else repr(r[k]) if isinstance(r.get(k), float) else r.get(k, "")) for k in FIELDS})
    finish(rows, best, info)


def finish(rows, best, info):
    text = summarize(rows, best, info)
    open(os.path.join(RESULTS, "summary.md"), "w").write(text)
    update_readme(text)
    plot(rows, best)
    print("wrote " + index_page.write_index("optimizers", RESULTS))
    print(text)


def load_rows():
    rows = []
    for r in csv.DictReader(open(os.path.join(RESULTS, "results.csv"))):
        for k in ("evaluations", "exit_code", "repeat"):
            r[k] = int(r[k]) if r[k] != "" else ""
        for k in ("seconds", "wall_seconds", "initial_objective", "objective"):
            r[k] = float(r[k]) if r[k] != "" else ""
        if r["start"] != "tool":
            r["start"] = int(r["start"])
        rows.append(r)
    return rows


if __name__ == "__main__":
    main()
