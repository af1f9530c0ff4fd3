"""The files of scripts/report.py: table.csv, table.md, error_vs_time.png and README.md (the page).

Observed order of convergence of a case: the least-squares slope p of log|error| against log h
over its resolutions (h the level's length scale, cases.json), and the slope q of log|error|
against log wall time (|error| ~ wall^q, q < 0: what a halving of the error costs).
"""

import csv
import math
import os
import platform

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["case", "model", "resolution", "value", "unknowns", "error", "ref", "band", "ok", "wall", "per_step",
           "per_simulated", "peak_mb", "steps", "simulated", "h", "detail", "reference", "command"]


def slope(xs, ys):
    """Least-squares slope of log y against log x (None with fewer than two points)."""
    pts = [(math.log(x), math.log(abs(y))) for x, y in zip(xs, ys) if x and y]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else None


def orders(rows):
    """Per case: (p in h, q in wall time), from its runs that produced an error."""
    out = {}
    for name in dict.fromkeys(r["case"] for r in rows):
        good = [r for r in rows if r["case"] == name and r["error"] is not None]
        p = slope([r["h"] for r in good], [r["error"] for r in good])
        q = slope([r["wall"] for r in good], [r["error"] for r in good])
        out[name] = (p, q)
    return out


def fmt(x, spec):
    return "n/a" if x is None else format(x, spec)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({**r, "band": f"[{r['band'][0]:g}, {r['band'][1]:g}]"})


def markdown_table(rows):
    lines = ["| case | model | resolution | unknowns | error | reference | band | in band | wall [s] | "
             "per step [s] | per simulated s [s] | peak [MB] | measured |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['model']} | {r['resolution']} | {fmt(r.get('unknowns'), ',')} | "
            f"{fmt(r['error'], '+.3e')} | {r['ref']} | [{r['band'][0]:g}, {r['band'][1]:g}] | "
            f"{'yes' if r['ok'] else '**no**'} | {r['wall']:.2f} | {fmt(r.get('per_step'), '.3g')} | "
            f"{fmt(r.get('per_simulated'), '.3g')} | {r['peak_mb']:.0f} | {r['detail']} |")
    return "\n".join(lines) + "\n"


def plot(path, cases, rows, order):
    """One panel per case (|error| against wall time, each point labelled with its resolution's
    value) and a last panel with every case's |error| against h."""
    shown = [c for c in cases if any(r["case"] == c["name"] and r["error"] for r in rows)]
    ncols = 3
    nrows = (len(shown) + ncols) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(5 * ncols, 3.9 * nrows), squeeze=False)
    panels = [ax for line in axes for ax in line]
    markers = "osD^v<>ph*"
    last = panels[len(shown)]
    for i, case in enumerate(shown):
        good = [r for r in rows if r["case"] == case["name"] and r["error"]]
        p, q = order[case["name"]]
        ax, style = panels[i], dict(marker=markers[i % len(markers)], color=f"C{i}")
        ax.loglog([r["wall"] for r in good], [abs(r["error"]) for r in good], **style)
        for r in good:
            ax.annotate(f"{r['value']:g}", (r["wall"], abs(r["error"])),
                        textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set_title(f"{case['name']} ({case['model']})", fontsize=9)
        ax.text(0.03, 0.05, f"order p = {fmt(p, '.2f')} in h\n|error| ~ wall^{fmt(q, '.2f')}",
                transform=ax.transAxes, fontsize=8)
        ax.set_xlabel("wall time [s]", fontsize=8)
        ax.set_ylabel(f"|error| vs {case['ref']}", fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
        ax.margins(0.25)
        last.loglog([r["h"] for r in good], [abs(r["error"]) for r in good], label=case["name"], **style)
    last.set_title("all cases: |error| against resolution h", fontsize=9)
    last.set_xlabel("h (cases.json, per case: edge, cell or spacing)", fontsize=8)
    last.grid(True, which="both", alpha=0.3)
    last.legend(fontsize=6.5)
    for ax in panels[len(shown) + 1:]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def machine(load_at_start):
    """The machine and its load during the run: the conditions the wall times were measured in (the
    commit and date of a committed page are git's)."""
    load = os.getloadavg()
    cpu = platform.processor() or platform.machine()
    for line in open("/proc/cpuinfo") if os.path.exists("/proc/cpuinfo") else []:
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    return f"{cpu}, {os.cpu_count()} cores, load average {load_at_start:.1f} at the start and {load[0]:.1f} at the end"


def page(cases, rows, order, total, command, quick, load):
    bad = [r for r in rows if not r["ok"]]
    lines = ["# Speed against error", "",
             f"Made by `{command}` in {total:.0f} s ({len(rows)} runs{', --quick' if quick else ''}; "
             f"{machine(load)}). {len(rows) - len(bad)} of {len(rows)} runs within their bands.", "",
             "- [table.md](table.md) (and [table.csv](table.csv)): every run: case, model, resolution, unknowns, "
             "error against the named reference, its band, wall time per step and per simulated second, peak memory",
             "- [error_vs_time.png](error_vs_time.png): |error| against wall time, one panel per case, log axes, with "
             "the observed order of convergence; the last panel: every case's |error| against its resolution h",
             "- [scaling.md](scaling.md) (and [scaling.csv](scaling.csv)): the coupled step on the flagship geometry "
             "at about 100k, 400k and 1M fluid tets, time per phase, peak memory, and its solvers side by side "
             "(`scripts/report_scaling.py --out " + "OUT`, run on its own: it takes longer than the cases)", "",
             "Wall time and peak resident memory are those of the whole process (meshing, set-up and output "
             "included; frames are not written). Unknowns: fluid pressure unknowns (fluid runner, bench_fluid's "
             "potential flow), pressure unknowns + solid dofs (coupled runner, largest step), 3 x nodes (tet and "
             "hex8 static runs), particles (mpm runner), the tank's mesh nodes (standing wave). The cases, their "
             "scenes and bands: `data/report/cases.json`; the error measures: `scripts/report_metrics.py`; WORK in "
             "table.csv's commands is the runs' folder (`--work`).", "",
             "## Cases", "",
             "| case | model | what | reference | error | observed order p (\\|error\\| ~ h^p) | q (\\|error\\| ~ wall^q) |",
             "|---|---|---|---|---|---|---|"]
    for c in cases:
        if c["name"] not in order:
            continue
        p, q = order[c["name"]]
        lines.append(f"| {c['name']} | {c['model']} | {c['title']} | {c['reference']} | {c['error']} | "
                     f"{fmt(p, '.2f')} | {fmt(q, '.2f')} |")
    if bad:
        lines += ["", "## Outside their bands", ""]
        lines += [f"- {r['case']}, {r['resolution']}: {fmt(r['error'], '+.3e')} against "
                  f"[{r['band'][0]:g}, {r['band'][1]:g}]: {r['detail']}" for r in bad]
    return "\n".join(lines) + "\n"


def write(out, cases, rows, total, command, quick, load):
    order = orders(rows)
    write_csv(os.path.join(out, "table.csv"), rows)
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("# Speed against error: every run\n\n" + markdown_table(rows))
    plot(os.path.join(out, "error_vs_time.png"), cases, rows, order)
    with open(os.path.join(out, "README.md"), "w") as f:
        f.write(page(cases, rows, order, total, command, quick, load))
