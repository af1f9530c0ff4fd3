#!/usr/bin/python3
"""The speed-against-error report: every model's validation cases at three or more resolutions.

    scripts/report.py [--quick] [--out DIR] [--build DIR] [--threads N] [--cases a,b] [--work DIR]

Runs the cases of data/report/cases.json (fluid, solid tet FEM, hex8 Total Lagrangian, coupling,
MPM + membranes, free-surface liquid), each through `tetfsi run` on its scene or through a
benchmark executable of apps/bench, one process per resolution, and writes into DIR (default
out/report): table.csv and table.md (case, model, resolution, unknowns, error against the named
reference, wall time per step and per simulated second, peak memory), error_vs_time.png (error
against wall time per case on log axes, with the observed order of convergence) and README.md, the
page that links them. Wall time and peak memory are the whole process's (os.wait4), meshing and
set-up included. Every case states its reference and, per resolution, the band its signed error
must lie in; the script exits 1 if any run fails or any error lies outside its band (`--quick`
runs only the resolutions marked quick: 19 runs in about 45 s; the full report 38 runs in about
4.5 minutes on the 2-core machine at load 1-2).
"""

import argparse
import copy
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import report_metrics  # noqa: E402
import report_output  # noqa: E402

CASES = os.path.join(ROOT, "data", "report", "cases.json")


def set_pointer(doc, pointer, value):
    """doc[pointer] = value for a JSON pointer (RFC 6901), creating missing objects on the way."""
    keys = [k.replace("~1", "/").replace("~0", "~") for k in pointer.lstrip("/").split("/")]
    for k in keys[:-1]:
        doc = doc[int(k)] if isinstance(doc, list) else doc.setdefault(k, {})
    if isinstance(doc, list):
        doc[int(keys[-1])] = value
    else:
        doc[keys[-1]] = value


def fill(value, names):
    """`value` with {dir}, {value}, ... replaced in every string it holds."""
    if isinstance(value, str):
        return value.format(**names)
    if isinstance(value, list):
        return [fill(v, names) for v in value]
    if isinstance(value, dict):
        return {k: fill(v, names) for k, v in value.items()}
    return value


def absolute_files(doc, folder):
    """Makes every relative "file" path of a scene absolute (the scene is run from another folder)."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            if k == "file" and isinstance(v, str) and not os.path.isabs(v):
                doc[k] = os.path.normpath(os.path.join(folder, v))
            else:
                absolute_files(v, folder)
    elif isinstance(doc, list):
        for v in doc:
            absolute_files(v, folder)


def run_process(cmd, log_path):
    """Runs cmd; returns (exit status, wall time [s], peak resident memory [MB], stdout)."""
    start = time.monotonic()
    with open(log_path, "w") as log:
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        out = p.stdout.read()
        _, status, usage = os.wait4(p.pid, 0)
        log.write(out)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    return code, wall, usage.ru_maxrss / 1024.0, out


def run_level(case, level, args, work):
    """One case at one resolution; returns the table row (a dict)."""
    folder = os.path.join(work, f"{case['name']}_{level['value']}")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    names = {"dir": folder, "value": level["value"], "python": sys.executable, "scripts": HERE}
    scene = None
    if "scene" in case:
        base = os.path.normpath(os.path.join(os.path.dirname(CASES), case["scene"]))
        scene = json.load(open(base))
        absolute_files(scene, os.path.dirname(base))
        for pointer, value in list(case.get("set", {}).items()) + list(level.get("set", {}).items()):
            set_pointer(scene, pointer, fill(copy.deepcopy(value), names))
        if "prepare" in case:
            code, _, _, out = run_process(fill(case["prepare"], names), os.path.join(folder, "prepare.log"))
            if code != 0:
                raise RuntimeError(f"{case['name']}: {' '.join(fill(case['prepare'], names))} failed:\n{out}")
        path = os.path.join(folder, "scene.json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
        cmd = [args.tetfsi, "run", path, "--out", os.path.join(folder, "out"), "--quiet"]
        if args.threads:
            cmd += ["--threads", str(args.threads)]
    else:
        cmd = [os.path.join(args.build, "apps", "bench", case["bench"])] + fill(case["args"], names)
    code, wall, peak, out = run_process(cmd, os.path.join(folder, "process.log"))
    row = {"case": case["name"], "model": case["model"], "resolution": fill(case["resolution"], names),
           "value": level["value"], "h": level.get("h", level["value"]), "ref": case["ref"],
           "reference": case["reference"],
           "band": level["band"], "wall": wall, "peak_mb": peak,
           "command": " ".join(cmd).replace(work, "WORK").replace(ROOT + os.sep, "")}
    if code != 0:
        row.update(error=None, detail=f"FAILED (exit {code}): {out.strip()[-300:]}", ok=False)
        return row
    try:
        r = report_metrics.METRICS[case["metric"]](
            report_metrics.Run(scene, os.path.join(folder, "out"), out, case.get("params", {})))
    except (OSError, ValueError, KeyError, IndexError, SystemExit) as e:
        row.update(error=None, detail=f"FAILED to read the result: {e}", ok=False)
        return row
    lo, hi = level["band"]
    row.update(error=r.error, detail=r.detail, unknowns=r.unknowns, steps=r.steps, simulated=r.simulated,
               per_step=wall / max(r.steps, 1), per_simulated=wall / r.simulated if r.simulated else None,
               ok=lo <= r.error <= hi)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="only the resolutions marked quick (about 45 s)")
    ap.add_argument("--out", default=os.path.join("out", "report"), help="folder of the table, plot and page")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the CMake build folder")
    ap.add_argument("--tetfsi", help="the tetfsi executable (default BUILD/apps/tetfsi)")
    ap.add_argument("--threads", type=int, default=0, help="--threads of tetfsi run (default: tetfsi's)")
    ap.add_argument("--cases", help="comma-separated case names (default: all)")
    ap.add_argument("--work", help="folder for the runs' output (default: a temporary folder, removed)")
    args = ap.parse_args()
    args.tetfsi = args.tetfsi or os.path.join(args.build, "apps", "tetfsi")
    cases = json.load(open(CASES))["cases"]
    if args.cases:
        wanted = args.cases.split(",")
        unknown = set(wanted) - {c["name"] for c in cases}
        if unknown:
            sys.exit(f"report.py: unknown case(s) {', '.join(sorted(unknown))}")
        cases = [c for c in cases if c["name"] in wanted]
    work = args.work or tempfile.mkdtemp(prefix="tetfsi_report_")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    rows, start, load = [], time.monotonic(), os.getloadavg()[0]
    try:
        for case in cases:
            for level in case["levels"]:
                if args.quick and not level.get("quick"):
                    continue
                row = run_level(case, level, args, work)
                rows.append(row)
                err = "n/a" if row["error"] is None else f"{row['error']:+.3e}"
                print(f"{'ok ' if row['ok'] else 'OUT'} {row['case']:<22} {row['resolution']:<40} error {err} "
                      f"band [{row['band'][0]:g}, {row['band'][1]:g}]  {row['wall']:.1f} s  {row['peak_mb']:.0f} MB"
                      + ("" if row["ok"] else f"  {row['detail']}"), flush=True)
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    total = time.monotonic() - start
    report_output.write(args.out, cases, rows, total, " ".join(["scripts/report.py"] + sys.argv[1:]), args.quick, load)
    bad = [r for r in rows if not r["ok"]]
    print(f"{len(rows)} runs in {total:.0f} s; report in {os.path.join(args.out, 'README.md')}")
    print(f"{len(rows) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
