"""The files of scripts/report.py: table.csv, table.md, error_vs_time.png, peer_<problem>.png
(cases with a peer) and README.md (the page).

Observed order of convergence of a case: the least-squares slope p of log|error| against log h
over its resolutions (h the level's length scale, cases.json), and the slope q of log|error|
against log wall time (|error| ~ wall^q, q < 0: what a halving of the error costs); for tetfsi and
for the peer (OpenFOAM) separately.
"""

import csv
import math
import os
import platform
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["case", "model", "code", "resolution", "value", "cells", "unknowns", "error", "ref", "band", "ok", "wall",
           "cpu", "per_step", "per_simulated", "peak_mb", "steps", "simulated", "h", "detail", "reference", "command"]
TETFSI = "tetfsi"
LIQUID_COMMAND = ("scripts/report.py --cases sloshing,dam_break,liquid_volume,floating_block,standing_wave "
                  "--out docs/report/liquid --work /tmp/report_liquid_work")


def expanded(cases):
    """The cases and their `also` errors as cases of their own (model and title from the parent)."""
    out = []
    for c in cases:
        out.append(c)
        for extra in c.get("also", []):
            out.append({"model": c["model"], "title": c["title"], "h_unit": c.get("h_unit"), **extra,
                        "peer": c.get("peer")})
    return out


def cell(text):
    """Text for a Markdown table cell: its bars escaped."""
    return str(text).replace("|", "\\|")


def band_text(band):
    return "peer" if band is None else f"[{band[0]:g}, {band[1]:g}]"


def count_text(n):
    """12345 -> '12k' (cell counts on the plots)."""
    if n is None:
        return None
    return f"{n / 1000:.3g}k" if n >= 1000 else str(n)


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
    """Per (case, code): (p in h, q in wall time), from its runs that produced an error."""
    out = {}
    for key in dict.fromkeys((r["case"], r.get("code", TETFSI)) for r in rows):
        good = [r for r in rows if (r["case"], r.get("code", TETFSI)) == key and r["error"] is not None]
        p = slope([r["h"] for r in good], [r["error"] for r in good])
        q = slope([r["wall"] for r in good], [r["error"] for r in good])
        out[key] = (p, q)
    return out


def fmt(x, spec):
    return "n/a" if x is None else format(x, spec)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({**r, "band": band_text(r["band"])})


def markdown_table(rows):
    lines = ["| case | model | code | resolution | cells | unknowns | error | reference | band | in band | wall [s] | "
             "CPU [s] | per step [s] | per simulated s [s] | peak [MB] | measured |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        verdict = "peer" if r["band"] is None and r["ok"] else ("yes" if r["ok"] else "**no**")
        lines.append(
            f"| {r['case']} | {r['model']} | {r.get('code', TETFSI)} | {r['resolution']} | "
            f"{fmt(r.get('cells'), ',')} | "
            f"{fmt(r.get('unknowns'), ',')} | {fmt(r['error'], '+.3e')} | {r['ref']} | {band_text(r['band'])} | "
            f"{verdict} | {r['wall']:.2f} | {fmt(r.get('cpu'), '.2f')} | {fmt(r.get('per_step'), '.3g')} | "
            f"{fmt(r.get('per_simulated'), '.3g')} | {r['peak_mb']:.0f} | {cell(r['detail'])} |")
    return "\n".join(lines) + "\n"


def series(ax, rows, order, name, code, style, label=None):
    """One code's runs of a case on a panel: |error| against wall time, each point labelled with its
    cell count (or its resolution's value); returns the order text."""
    good = [r for r in rows if r["case"] == name and r.get("code", TETFSI) == code and r["error"]]
    if not good:
        return None
    ax.loglog([r["wall"] for r in good], [abs(r["error"]) for r in good], label=label, **style)
    for r in good:
        text = count_text(r.get("cells")) or f"{r['value']:g}"
        ax.annotate(text, (r["wall"], abs(r["error"])), textcoords="offset points", xytext=(4, 4), fontsize=7,
                    color=style.get("color"))
    p, q = order[(name, code)]
    return f"{code}: p = {fmt(p, '.2f')} in h, |error| ~ wall^{fmt(q, '.2f')}"


PEER_STYLE = dict(marker="s", color="0.35", linestyle="--", markerfacecolor="none")


def plot(path, cases, rows, order):
    """One panel per case (|error| against wall time, each point labelled with its cell count or
    its resolution's value; the peer's runs beside tetfsi's) and a last panel with every case's
    |error| against h."""
    shown = [c for c in expanded(cases) if any(r["case"] == c["name"] and r["error"] for r in rows)]
    ncols = 3
    nrows = (len(shown) + ncols) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(5 * ncols, 3.9 * nrows), squeeze=False)
    panels = [ax for line in axes for ax in line]
    markers = "osD^v<>ph*"
    last = panels[len(shown)]
    for i, case in enumerate(shown):
        good = [r for r in rows if r["case"] == case["name"] and r.get("code", TETFSI) == TETFSI and r["error"]]
        ax, style = panels[i], dict(marker=markers[i % len(markers)], color=f"C{i % 10}")
        texts = [series(ax, rows, order, case["name"], TETFSI, style, TETFSI)]
        peers = sorted({r["code"] for r in rows if r["case"] == case["name"] and r.get("code", TETFSI) != TETFSI})
        texts += [series(ax, rows, order, case["name"], code, PEER_STYLE, code) for code in peers]
        if peers:
            ax.legend(fontsize=6.5, loc="upper right")
        ax.set_title(f"{case['name']} ({case['model']})", fontsize=9)
        ax.text(0.03, 0.05, "\n".join(t for t in texts if t), transform=ax.transAxes, fontsize=7)
        ax.set_xlabel("wall time [s]", fontsize=8)
        ax.set_ylabel(f"|error| vs {case['ref']}", fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
        ax.margins(0.25)
        if good:
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


def peer_plots(out, cases, rows, order):
    """peer_<problem>.png per case with a peer: a panel per error of the problem (the case's and its
    `also`'s), |error| against wall time for tetfsi and the peer, cell counts stated; returns the
    file names written."""
    written = []
    for case in cases:
        if "peer" not in case or not any(r["case"] == case["name"] and r.get("code", TETFSI) != TETFSI
                                          for r in rows):
            continue
        names = [case] + case.get("also", [])
        fig, axes = plt.subplots(1, len(names), figsize=(5.2 * len(names), 4.2), squeeze=False)
        for ax, c in zip(axes[0], names):
            texts = [series(ax, rows, order, c["name"], TETFSI, dict(marker="o", color="C0"), "tetfsi (tets)")]
            for code in sorted({r["code"] for r in rows if r["case"] == c["name"] and r.get("code", TETFSI) != TETFSI}):
                texts.append(series(ax, rows, order, c["name"], code, PEER_STYLE, f"{code} (2D cells)"))
            ax.set_title("\n".join(textwrap.wrap(f"{c['name']}: {c['error']}", 70)), fontsize=7.5)
            ax.text(0.03, 0.05, "\n".join(t for t in texts if t), transform=ax.transAxes, fontsize=7)
            ax.set_xlabel("wall time [s], one core", fontsize=8)
            ax.set_ylabel(f"|error| vs {c['ref']}", fontsize=8)
            ax.grid(True, which="both", alpha=0.3)
            ax.margins(0.25)
            ax.legend(fontsize=7, loc="upper right")
        fig.suptitle("\n".join(textwrap.wrap(case["title"], 150)), fontsize=8.5)
        fig.tight_layout()
        name = f"peer_{case['peer']['problem']}.png"
        fig.savefig(os.path.join(out, name), dpi=80)
        plt.close(fig)
        written.append(name)
    return written


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


def page(out, cases, rows, order, total, command, quick, load, peer="", peer_files=()):
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
             "(`scripts/report_scaling.py --out " + "OUT`, run on its own: it takes longer than the cases)"]
    lines = lines[:-1] if not os.path.exists(os.path.join(out, "scaling.md")) else lines
    lines += [f"- [{f}]({f}): the {f[5:-4].replace('_', ' ')} problem, tetfsi and the peer on the same axes: "
              "|error| against wall time (one core each), cell counts stated" for f in peer_files]
    if os.path.exists(os.path.join(out, "liquid", "README.md")):
        lines.append("- [liquid/](liquid/README.md): the liquid cases alone, with OpenFOAM's interFoam beside tetfsi "
                     "(`" + LIQUID_COMMAND + "`)")
    if os.path.exists(os.path.join(out, "flagship.md")):  # written by hand, dated: kept by the report
        lines.append("- [flagship.md](flagship.md): the flagship scene's time, memory and output size, and the "
                     "tools its output was checked with")
    lines += ["", f"Peer: {peer}. The peer's rows (code OpenFOAM) have no band: they are the comparison, not a "
              "test. OpenFOAM runs 2D (one cell thick, scripts/openfoam_peer.py), tetfsi a slab or thin tank of "
              "tets; both on one core.", "",
             "Wall time and peak resident memory are those of the whole process (meshing, set-up and output "
             "included; frames are not written). Unknowns: fluid pressure unknowns (fluid runner, bench_fluid's "
             "potential flow), pressure unknowns + solid dofs (coupled runner, largest step), 3 x nodes (tet and "
             "hex8 static runs), particles (mpm runner), the tank's mesh nodes (standing wave). The cases, their "
             "scenes and bands: `data/report/cases.json`; the error measures: `scripts/report_metrics.py`; WORK in "
             "table.csv's commands is the runs' folder (`--work`).", "",
             "## Cases", "",
             "| case | model | what | reference | error | observed order p (\\|error\\| ~ h^p) "
             "| q (\\|error\\| ~ wall^q) | peer's p, q |",
             "|---|---|---|---|---|---|---|---|"]
    for c in expanded(cases):
        if (c["name"], TETFSI) not in order:
            continue
        p, q = order[(c["name"], TETFSI)]
        peers = [f"{k[1]}: {fmt(v[0], '.2f')}, {fmt(v[1], '.2f')}" for k, v in order.items()
                 if k[0] == c["name"] and k[1] != TETFSI]
        lines.append(f"| {c['name']} | {c['model']} | {cell(c['title'])} | {cell(c['reference'])} | "
                     f"{cell(c['error'])} | "
                     f"{fmt(p, '.2f')} | {fmt(q, '.2f')} | {'; '.join(peers) or ''} |")
    notes = [f"- {c['name']}: {c['notes']}" for c in cases if c.get("notes") and (c["name"], TETFSI) in order]
    if notes:
        lines += ["", "## Notes", ""] + notes
    if bad:
        lines += ["", "## Outside their bands", ""]
        lines += [f"- {r['case']} ({r.get('code', TETFSI)}), {r['resolution']}: {fmt(r['error'], '+.3e')} against "
                  f"{band_text(r['band'])}: {r['detail']}" for r in bad]
    return "\n".join(lines) + "\n"


def write(out, cases, rows, total, command, quick, load, peer=""):
    order = orders(rows)
    write_csv(os.path.join(out, "table.csv"), rows)
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("# Speed against error: every run\n\n" + markdown_table(rows))
    plot(os.path.join(out, "error_vs_time.png"), cases, rows, order)
    peer_files = peer_plots(out, cases, rows, order)
    with open(os.path.join(out, "README.md"), "w") as f:
        f.write(page(out, cases, rows, order, total, command, quick, load, peer, peer_files))
