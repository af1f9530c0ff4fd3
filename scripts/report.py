#!/usr/bin/python3
"""The speed-against-error report: every model's validation cases at three or more resolutions.

    scripts/report.py [--quick] [--out DIR] [--build DIR] [--threads N] [--cases a,b] [--work DIR]
                      [--no-peer]

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

Peer: a case with a `peer` entry (the sloshing tank, the dam break) is also run by OpenFOAM's
interFoam at the peer's resolutions (scripts/openfoam_peer.py), on one core, and its rows sit
beside tetfsi's in the table and the plots (peer_<problem>.png: error against wall time, both
codes, cell counts stated). Only where OpenFOAM is installed (Debian: `apt-get install openfoam`;
scripts/setup.sh does not install it) and never with --quick or --no-peer; the page says which.
A case's `threads` runs its tetfsi levels on that many threads (1 for the cases compared with the
single-core peer). A case's `also` lists further errors measured on the same runs (the metric
returns them), each a case of its own in the table, at the levels that give it a band (`also` of
the level).
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
import openfoam_peer  # noqa: E402
import report_metrics  # noqa: E402
import report_output  # noqa: E402

CASES = os.path.join(ROOT, "data", "report", "cases.json")


def set_pointer(doc, pointer, value):
    """doc[pointer] = value for a JSON pointer (RFC 6901), creating missing objects on the way; a
    last key "-" appends to an array."""
    keys = [k.replace("~1", "/").replace("~0", "~") for k in pointer.lstrip("/").split("/")]
    for k in keys[:-1]:
        doc = doc[int(k)] if isinstance(doc, list) else doc.setdefault(k, {})
    if isinstance(doc, list) and keys[-1] == "-":
        doc.append(value)
    elif isinstance(doc, list):
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


def run_process(cmd, log_path, usage_out=None):
    """Runs cmd; returns (exit status, wall time [s], peak resident memory [MB], stdout). The
    process's CPU time (user + system) [s] is stored in usage_out["cpu"] if given."""
    start = time.monotonic()
    with open(log_path, "w") as log:
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        out = p.stdout.read()
        _, status, usage = os.wait4(p.pid, 0)
        log.write(out)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    if usage_out is not None:
        usage_out["cpu"] = usage.ru_utime + usage.ru_stime
    return code, wall, usage.ru_maxrss / 1024.0, out


def also_rows(case, level, row, result):
    """The rows of the case's `also` errors that the level gives a band (its `also`), measured on
    the run of `row` (result.also[name] = (error, detail)); a failed run fails them too."""
    rows = []
    for extra in case.get("also", []):
        if extra["name"] not in level.get("also", {}):
            continue
        r = dict(row, case=extra["name"], ref=extra["ref"], reference=extra["reference"],
                 band=level["also"][extra["name"]])
        if result is not None:
            error, detail = result.also[extra["name"]]
            lo, hi = r["band"]
            r.update(error=error, detail=detail, ok=lo <= error <= hi)
        rows.append(r)
    return rows


def run_level(case, level, args, work):
    """One case at one resolution; returns its table rows (dicts): the case's, then its `also`'s."""
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
        threads = case.get("threads", args.threads)
        if threads:
            cmd += ["--threads", str(threads)]
    else:
        cmd = [os.path.join(args.build, "apps", "bench", case["bench"])] + fill(case["args"], names)
    usage = {}
    code, wall, peak, out = run_process(cmd, os.path.join(folder, "process.log"), usage)
    row = {"case": case["name"], "model": case["model"], "code": "tetfsi",
           "resolution": fill(case["resolution"], names),
           "value": level["value"], "h": level.get("h", level["value"]), "ref": case["ref"],
           "reference": case["reference"],
           "band": level["band"], "wall": wall, "cpu": usage["cpu"], "peak_mb": peak,
           "command": " ".join(cmd).replace(work, "WORK").replace(ROOT + os.sep, "")}
    if code != 0:
        row.update(error=None, detail=f"FAILED (exit {code}): {out.strip()[-300:]}", ok=False)
        return [row] + also_rows(case, level, row, None)
    try:
        r = report_metrics.METRICS[case["metric"]](
            report_metrics.Run(scene, os.path.join(folder, "out"), out, case.get("params", {})))
    except (OSError, ValueError, KeyError, IndexError, SystemExit) as e:
        row.update(error=None, detail=f"FAILED to read the result: {e}", ok=False)
        return [row] + also_rows(case, level, row, None)
    lo, hi = level["band"]
    row.update(error=r.error, detail=r.detail, unknowns=r.unknowns, cells=r.cells, steps=r.steps,
               simulated=r.simulated, per_step=wall / max(r.steps, 1),
               per_simulated=wall / r.simulated if r.simulated else None, ok=lo <= r.error <= hi)
    return [row] + also_rows(case, level, row, r)


def run_peer(case, level, work):
    """The case's problem run by OpenFOAM at one of the peer's resolutions; returns its rows (one
    per error the peer maps to a case: `peer.errors`, case name -> key of openfoam_peer's result).
    Peer rows have no band: they are the comparison, not a test."""
    peer = case["peer"]
    names = {"value": level["value"]}
    base = {"model": case["model"], "code": peer["code"], "resolution": fill(peer["resolution"], names),
            "value": level["value"], "h": level.get("h", level["value"]), "band": None, "ok": True,
            "command": f"scripts/openfoam_peer.py {peer['problem']} --cells {level['value']} --work WORK"}
    try:
        r = openfoam_peer.run(peer["problem"], level["value"], work)
    except (OSError, RuntimeError, ValueError, KeyError, IndexError) as e:
        return [dict(base, case=name, ref="", reference="", wall=0.0, cpu=None, peak_mb=0.0, error=None,
                     detail=f"FAILED: {e}", ok=False) for name in peer["errors"]]
    refs = {c["name"]: c for c in [case] + case.get("also", [])}
    return [dict(base, case=name, ref=refs[name]["ref"], reference=refs[name]["reference"], error=r[key],
                 detail=r["detail"], unknowns=r["cells"], cells=r["cells"], steps=r["steps"],
                 simulated=r["simulated"], wall=r["wall"], cpu=r["cpu"], peak_mb=r["peak_mb"],
                 per_step=r["wall"] / max(r["steps"], 1), per_simulated=r["wall"] / r["simulated"])
            for name, key in peer["errors"].items()]


def peer_status(args, cases):
    """Whether the peer runs, in words for the page: 'OpenFOAM vNNNN (interFoam), one core' or why not."""
    if not any("peer" in c for c in cases):
        return "no case with a peer selected"
    if args.quick:
        return "not run (--quick)"
    if args.no_peer:
        return "not run (--no-peer)"
    if not openfoam_peer.available():
        return ("not run: OpenFOAM is not installed (blockMesh, setFields, interFoam not on the PATH; "
                "Debian: apt-get install openfoam)")
    return f"OpenFOAM v{openfoam_peer.version()} (interFoam), one core"


def print_row(row):
    err = "n/a" if row["error"] is None else f"{row['error']:+.3e}"
    band = "peer" if row["band"] is None else f"band [{row['band'][0]:g}, {row['band'][1]:g}]"
    print(f"{'ok ' if row['ok'] else 'OUT'} {row['case']:<22} {row['code'][:8]:<8} {row['resolution']:<40} "
          f"error {err} {band}  {row['wall']:.1f} s  {row['peak_mb']:.0f} MB"
          + ("" if row["ok"] else f"  {row['detail']}"), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="only the resolutions marked quick (about 45 s)")
    ap.add_argument("--out", default=os.path.join("out", "report"), help="folder of the table, plot and page")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the CMake build folder")
    ap.add_argument("--tetfsi", help="the tetfsi executable (default BUILD/apps/tetfsi)")
    ap.add_argument("--threads", type=int, default=0, help="--threads of tetfsi run (default: tetfsi's)")
    ap.add_argument("--cases", help="comma-separated case names (default: all)")
    ap.add_argument("--work", help="folder for the runs' output (default: a temporary folder, removed)")
    ap.add_argument("--no-peer", action="store_true", help="do not run OpenFOAM even where it is installed")
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
    peer = peer_status(args, cases)
    print(f"peer: {peer}", flush=True)
    try:
        for case in cases:
            for level in case["levels"]:
                if args.quick and not level.get("quick"):
                    continue
                for row in run_level(case, level, args, work):
                    rows.append(row)
                    print_row(row)
            if "peer" in case and peer.startswith("OpenFOAM"):
                for level in case["peer"]["levels"]:
                    for row in run_peer(case, level, work):
                        rows.append(row)
                        print_row(row)
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    total = time.monotonic() - start
    report_output.write(args.out, cases, rows, total, " ".join(["scripts/report.py"] + sys.argv[1:]), args.quick, load,
                        peer)
    bad = [r for r in rows if not r["ok"]]
    print(f"{len(rows)} runs in {total:.0f} s; report in {os.path.join(args.out, 'README.md')}")
    print(f"{len(rows) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
