"""index.html for the shipped studies that scripts run (optimizers, gradient_cost, scaling), as `tether study`
writes it for its own (docs/reports.md): the summary, the figures and the results as a sortable, filterable table.
Their rows are runs of the tools (an optimizer's run, a benchmark's timing), which keep no motion: the page has no
viewer column.

    python3 studies/index_page.py optimizers|gradient_cost|scaling

Each study's run.py calls it when it finishes; run alone it writes the page from the results in the repository.
The page is viewer/assets/study.html and study.js, filled as the tether binary fills them. Standard library only.
"""
import csv
import json
import math
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def number(text):
    """A cell as a number (None for nan or empty), or the text itself."""
    if text is None or text.strip() == "":
        return None
    try:
        x = float(text)
    except (TypeError, ValueError):
        return text
    return None if math.isnan(x) else x


def optimizers_rows(folder):
    """results.csv: a row per tool run; the status names its message."""
    with open(os.path.join(folder, "results.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    pointers = ["problem", "kind", "optimizer", "start", "repeat"]
    metrics = ["evaluations", "seconds", "wall_seconds", "initial_objective", "objective", "relative", "success"]
    rows = [{"values": [number(r[p]) for p in pointers], "metrics": [number(r[m]) for m in metrics],
             "status": r["status"] + (": " + r["message"] if r["message"] else "")} for r in table]
    with open(os.path.join(folder, "run_info.json")) as f:
        info = json.load(f)
    context = ["%s; %d tether runs in %.0f s, %s" % (info["machine"], len(rows), info["total"], info["date"])]
    return pointers, metrics, rows, context


def benchmark_rows(folder):
    """results.json of Google Benchmark: a row per benchmark (and aggregate), times in ms, its counters."""
    with open(os.path.join(folder, "results.json")) as f:
        results = json.load(f)
    standard = {"name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
                "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name",
                "aggregate_unit", "error_occurred", "error_message"}
    counters = sorted({k for b in results["benchmarks"] for k, v in b.items()
                       if k not in standard and isinstance(v, (int, float))})
    metrics = ["real_time_ms", "cpu_time_ms", "iterations"] + counters
    rows = []
    for b in results["benchmarks"]:
        scale = TO_MS[b.get("time_unit", "ns")]
        values = [b["real_time"] * scale, b["cpu_time"] * scale, b.get("iterations")] + [b.get(c) for c in counters]
        rows.append({"values": [b["name"]], "metrics": [None if v is None else float(v) for v in values],
                     "status": "error: " + b["error_message"] if b.get("error_occurred") else "ok"})
    c = results["context"]
    context = ["%s, %d CPUs at %d MHz, %s" % (c.get("host_name", "?"), c.get("num_cpus", 0),
                                              c.get("mhz_per_cpu", 0), c.get("date", "?"))]
    return ["name"], metrics, rows, context


STUDIES = {"optimizers": ("studies/optimizers/results", optimizers_rows),
           "gradient_cost": ("studies/gradient_cost", benchmark_rows),
           "scaling": ("studies/scaling", benchmark_rows)}


def in_script(text):
    return text.replace("</", "<\\/")  # as the binary writes a script's text (html_text.h)


def write_index(name, folder=None):
    """Writes FOLDER/index.html (the study's own results folder by default) from the results there."""
    where, read = STUDIES[name]
    folder = folder or os.path.join(ROOT, where)
    pointers, metrics, rows, context = read(folder)
    for k, row in enumerate(rows):
        row.update(index=k, view=False)
    study = {"study": "studies/%s/run.py" % name, "scenes": [], "pointers": pointers, "metrics": metrics,
             "rows": rows, "figures": sorted(f for f in os.listdir(folder) if f.endswith(".png")), "best": context}
    with open(os.path.join(ROOT, "viewer", "assets", "study.html")) as f:
        page = f.read()
    with open(os.path.join(ROOT, "viewer", "assets", "study.js")) as f:
        script = f.read()
    title = "tether study " + name
    start = 0  # the markers in their order, none searched for in text put in
    for marker, text in (("@TITLE@", title), ("@TITLE@", title),
                         ("@DATA@", in_script(json.dumps(study, allow_nan=False))),
                         ("@VIEWER@", '""'), ("@STUDY@", script)):
        at = page.index(marker, start)
        page = page[:at] + text + page[at + len(marker):]
        start = at + len(text)
    path = os.path.join(folder, "index.html")
    with open(path + ".partial", "w") as f:
        f.write(page)
    os.replace(path + ".partial", path)
    return path


if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in STUDIES:
        sys.exit("usage: python3 studies/index_page.py " + "|".join(STUDIES))
    print("wrote " + os.path.relpath(write_index(sys.argv[1]), ROOT))
