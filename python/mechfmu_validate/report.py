"""The report of ``mechfmu validate --report DIR``: ``DIR/index.md``, ``DIR/index.html`` and
one PNG per case (``DIR/<FMU>/<case>.png``): the FMU's signals against the reference, and the
error over time on a log scale (with the tolerance, and the other importers' runs' errors, as
each importer's declaration draws them: :attr:`~.importer.Importer.curves`).
``--readme DIR`` writes the tables (``DIR/validation.md``) and the highlighted cases' PNGs
(``DIR/validation/<name>.png``) with these plots and cells (:mod:`.validation_tables`).
"""

from __future__ import annotations

import html
import math
import re
from types import SimpleNamespace
from pathlib import Path
from typing import Any

import numpy as np

from .importer import CS, FMI2, FMI3, ME, Curve, row_name
from .importers import IMPORTERS, REFERENCE
from .model_exchange import band_text
from .rows import Row

__all__ = ["plot_case", "write_report", "markdown_table", "number_text", "limit_text", "result_text",
           "platform_lines", "versions_text"]

#: how each run's error over time is drawn, by importer column
CURVES: dict[str, Curve] = {name: curve for importer in IMPORTERS for name, curve in importer.curves.items()}

COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf"]
FLOOR = 1e-17  # zeros on the log scale


def number_text(x: Any) -> str:
    """A number in a table: two significant digits, ``-`` for none."""
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    if x == 0:
        return "0"
    if not math.isfinite(x):
        return str(x)
    return f"{x:.1e}"


def limit_text(row: Row, fmt=number_text) -> str:
    """A row's tolerance cell: the limit, or for a fixed-step Model Exchange row judged by
    its order, the observed order and the band it must lie in."""
    if row.get("observed_order") is not None:
        return f"order {row['observed_order']:.2f} in {band_text(row['order_band'])}, h {row['step']:g} s"
    return fmt(row.get("tolerance"))


def result_text(row: Row) -> str:
    """PASS, FAIL, SKIP, or LIMIT: the importer's solver did not reach the case's limit, the
    error it reached is reported (Model Exchange rows; not a failure)."""
    if row.get("skipped"):
        return "SKIP"
    if row.get("limited"):
        return "LIMIT"
    return "PASS" if row["passed"] else "FAIL"


def _panels(entry: dict[str, Any]) -> tuple[list[tuple[str, list]], dict[str, str], list]:
    """What the plot draws: the signals against the reference, in up to three panels by unit;
    each drawn signal's color; the signals whose errors are drawn in grey (when the colors do
    not suffice)."""
    ev = entry["evaluation"]
    result = entry.get("result")
    by_name = {s.name: s for s in ev.signals if s.fmu is not None}

    def recorded_only(name):
        """A recorded FMU variable that is not compared: drawn without a reference."""
        if result is None or name not in result:
            return None
        return SimpleNamespace(name=name, fmu=result[name], reference=None)

    if entry.get("plot"):
        top = [by_name.get(n) or recorded_only(n) for n in entry["plot"]]
        top = [s for s in top if s is not None]
    else:
        top = [s for s in by_name.values() if np.ptp(s.reference) > 1e-6 * max(np.max(np.abs(s.reference)), 1e-300)]
        if not top and result is not None:  # an invariant: show the motion it was checked on
            top = [recorded_only(n) for n in result.names() if n not in by_name and np.ptp(result[n]) > 0]
        top = top[:8]
    units = entry.get("units", {})
    groups: list[tuple[str, list]] = []
    for s in top:
        u = units.get(s.name, "")
        for g in groups:
            if g[0] == u:
                g[1].append(s)
                break
        else:
            groups.append((u, [s]))
    groups = groups[:3]
    shown = [s for _, g in groups for s in g]
    colors = {s.name: COLORS[i % len(COLORS)] for i, s in enumerate(shown)}
    rest = [s for s in ev.signals if s.name not in colors]
    if len(shown) + len(rest) <= len(COLORS):
        for i, s in enumerate(rest):
            colors[s.name] = COLORS[(len(shown) + i) % len(COLORS)]
        rest = []
    return groups, colors, rest


def _heading(fig, entry: dict[str, Any], fig_h: float) -> None:
    """The case, its verdict, its errors against the reference and the other importers, its settings."""
    worst = entry["evaluation"].worst
    status = "PASS" if entry["passed"] else "FAIL"
    fig.text(0.08, 1 - 0.1 / fig_h, f"{entry['fmu']} — {entry['case']}: {status}", fontsize=13, fontweight="bold",
             color="#1a7f37" if entry["passed"] else "#cf222e", ha="left", va="top")
    sub = []
    if worst is not None:
        sub.append(f"{entry.get('label', 'FMPy')}: max error {worst.max_error:.1e} ({worst.name}), "
                   f"tolerance {worst.tolerance:.0e}")
    for name, deviation in entry.get("deviations", {}).items():
        heading = CURVES[name].heading
        if heading is not None and deviation.get("max_error") is not None:
            sub.append(heading(deviation))
    line1 = ";   ".join(sub)
    settings = entry.get("settings") or ""
    if len(settings) > 130:
        settings = settings[:128] + " …"
    fig.text(0.08, 1 - 0.38 / fig_h, line1 + ("\n" + settings if settings else ""),
             fontsize=9, color="#57606a", ha="left", va="top", linespacing=1.4)


def _errors(ax, entry: dict[str, Any], colors: dict[str, str], rest: list) -> None:
    """The bottom panel: every signal's error over time, the tolerances, and the other
    importers' deviations from FMPy, on a log scale."""
    ev = entry["evaluation"]
    t = ev.time
    for s in rest:
        ax.semilogy(t, np.maximum(s.error, FLOOR), color="#b0b7c0", lw=0.8)
    if rest:
        ax.plot([], [], color="#b0b7c0", lw=0.8, label=f"{len(rest)} other signals")
    for s in ev.signals:
        if s.name in colors:
            ax.semilogy(t, np.maximum(s.error, FLOOR), color=colors[s.name], lw=1.2, label=s.name)
    tols = sorted({s.tolerance for s in ev.signals})
    for i, tol in enumerate(tols):
        ax.axhline(tol, color="#cf222e", ls="--", lw=1.2, label="tolerance" if i == 0 else None)
    for name, deviation in entry.get("deviations", {}).items():
        curve = CURVES[name]
        error = deviation.get("error_over_time")
        if error is None or (curve.only_nonzero and not np.any(error > 0)):
            continue
        ax.semilogy(deviation["time"], np.maximum(error, FLOOR), color=curve.color, lw=1.0, ls=curve.dashes,
                    label=curve.label)
        if curve.tolerance_label is not None:
            ax.axhline(deviation["tolerance"], color=curve.color, ls="--", lw=0.9, label=curve.tolerance_label)
    ax.set_ylabel("|FMU − ref| / scale")
    ax.set_xlabel("time (s)")
    ax.grid(True, which="major", color="#e5e7eb")
    lo = min([FLOOR * 10] + [float(np.min(np.maximum(s.error, FLOOR))) for s in ev.signals])
    hi = max([1.0] + [t_ * 10 for t_ in tols])
    ax.set_ylim(max(lo / 3, FLOOR), hi)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, frameon=False)
    ax.set_xlim(t[0], t[-1])


def plot_case(entry: dict[str, Any], path: Path) -> None:
    """One PNG: FMU vs reference (panels by unit), and the errors over time (log scale)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups, colors, rest = _panels(entry)
    n_top = max(len(groups), 1)
    fig_h = 2.3 * n_top + 2.9 + 0.9
    fig = plt.figure(figsize=(10, fig_h), dpi=110)
    heights = [2.3] * n_top + [2.9]
    gs = fig.add_gridspec(n_top + 1, 1, height_ratios=heights, hspace=0.3,
                          left=0.08, right=0.78, top=1 - 0.95 / fig_h, bottom=0.5 / fig_h)
    t = entry["evaluation"].time
    _heading(fig, entry, fig_h)
    ax0 = None
    for k, (unit, group) in enumerate(groups):
        ax = fig.add_subplot(gs[k, 0], sharex=ax0)
        ax0 = ax0 or ax
        for s in group:
            ax.plot(t, s.fmu, color=colors[s.name], lw=1.8, label=f"{s.name} (FMU)")
            if s.reference is not None:
                ax.plot(t, s.reference, color="black", lw=0.9, ls=(0, (4, 3)), alpha=0.85)
        if any(s.reference is not None for s in group):
            ax.plot([], [], color="black", lw=0.9, ls=(0, (4, 3)), label="reference")
        ax.set_ylabel(unit or "value")
        ax.grid(True, color="#e5e7eb")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, frameon=False)
        ax.tick_params(labelbottom=False)
    if not groups:
        ax = fig.add_subplot(gs[0, 0])
        ax.text(0.5, 0.5, "(an invariant check: no signal to plot against a reference)",
                ha="center", va="center", transform=ax.transAxes, color="#57606a")
        ax.set_axis_off()
    _errors(fig.add_subplot(gs[n_top, 0], sharex=ax0), entry, colors, rest)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)


def markdown_table(rows: list[Row]) -> str:
    lines = ["| FMU | case | importer | max error | tolerance | result |", "|---|---|---|---:|---:|---|"]
    for r in rows:
        result = result_text(r)
        lines.append(f"| {r['fmu']} | {r['case']} | {r['importer']} | {number_text(r['max_error'])} | "
                     f"{limit_text(r)} | {'**FAIL**' if result == 'FAIL' else result} |")
    return "\n".join(lines) + "\n"


def platform_lines(rows: list[Row]) -> list[str]:
    """One line per FMU: the platforms it has binaries for, which of them ran here, and how
    (the rows ``(platforms, ...)`` of :mod:`.platform_rows`)."""
    lines = []
    for r in rows:
        if "platforms" in r:
            found, run = r["platforms"]["found"], r["platforms"]["run"]
            named = r["platforms"].get("names", {})
            found, not_run, run = ([named.get(p, p) for p in group]
                                   for group in (found, [p for p in found if p not in run], run))
            lines.append(f"{r['fmu']} ({r['case'][len('(platforms, '):-1]}): binaries for {', '.join(found) or 'none'}; "
                         f"run: {', '.join(run)}" + (f"; not run: {', '.join(not_run)}" if not_run else "")
                         + "".join(f"; {n}" for n in r["notes"][1:]))
    return lines


def _html_table(rows: list[Row]) -> str:
    out = ["<table><tr><th>FMU</th><th>case</th><th>importer</th><th>max error</th><th>tolerance</th><th>result</th></tr>"]
    for r in rows:
        result = result_text(r)
        case = html.escape(r["case"])
        if r.get("anchor"):
            case = f'<a href="#{r["anchor"]}">{case}</a>'
        out.append(f"<tr><td>{html.escape(r['fmu'])}</td><td>{case}</td><td>{html.escape(r['importer'])}</td>"
                   f"<td class=num>{number_text(r['max_error'])}</td><td class=num>{html.escape(limit_text(r))}</td>"
                   f"<td class={result.lower()}>{result}</td></tr>")
    out.append("</table>")
    return "\n".join(out)


def _legend() -> str:
    """What the table's columns measure, from the importers' declarations."""
    me = [row_name(i.name, FMI2, ME, m) for i in IMPORTERS if i.runs.covers(ME, FMI2) for m in i.methods.get(FMI2, ())]
    return (
        "max error: " + "; ".join(i.words.report for i in IMPORTERS if i.words.report and i.runs.covers(CS, FMI2))
        + f". In Model Exchange ({', '.join(me)}) the "
        "error against the reference as under FMPy: CVode at relative tolerance 1e-10 is held to the case's "
        "tolerance; the fixed-step methods are run at h and h/2 and held to the case's tolerance or to their "
        "order: the observed order log2(e(h)/e(h/2)), whose band is shown, says the whole error is the "
        "method's truncation error. LIMIT: the importer's solver did not reach the case's tolerance (CVode "
        "up to 1e-6; a fixed-step method outside its asymptotic range, or limited by what the FMU holds to its "
        "own tolerance); the error reached is reported, not failed. The FMI 3.0 FMU of the mechanism "
        "(fmus/fmi3/<Name>.fmu) runs the same cases: "
        + "; ".join(i.words.report3 for i in IMPORTERS if i.words.report3 and i.runs.covers(CS, FMI3))
        + "; check: FMI 3.0 CS = FMI 2.0 CS compares every variable of the DefaultExperiment under both FMUs "
        "(1e-12, relative). For a check: the number of problems found."
    )


LEGEND = _legend()


def versions_text(header: dict[str, Any]) -> str:
    """``FMPy 0.3.32, ...``: each importer's version (or why it did not run), in the registry's order."""
    return ", ".join(f"{i.name} {header[i.header_key]}" if i is REFERENCE else header.get(i.header_key, "-")
                     for i in IMPORTERS)


def write_report(directory: Path, rows: list[Row], cases: list[dict[str, Any]],
                 header: dict[str, Any]) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    for entry in cases:
        # an FMU named by its path (two files of one model name): one folder, inside DIR
        folder = re.sub(r"[^\w.-]+", "_", entry["fmu"]).strip("_.") or "fmu"
        png = directory / folder / f"{entry['case']}.png"
        plot_case(entry, png)
        entry["png"] = png.relative_to(directory).as_posix()
    ok = all(r["passed"] for r in rows)
    summary = (f"{sum(r['passed'] for r in rows)} of {len(rows)} rows pass"
               + ("" if ok else f"; **{sum(not r['passed'] for r in rows)} fail**"))
    md = [f"# mechfmu validate: {'PASS' if ok else 'FAIL'}", "",
          f"{summary}. {versions_text(header)}, Python {header['python']}.", "",
          LEGEND, "", markdown_table(rows), "## Platforms", "",
          *[f"- {line}" for line in platform_lines(rows)], ""]
    for entry in cases:
        md += [f"## {entry['fmu']}: {entry['case']}", ""]
        if entry.get("description"):
            md += [entry["description"], ""]
        md += [f"Settings: {entry['settings']}", "", f"![{entry['fmu']} {entry['case']}]({entry['png']})", ""]
    (directory / "index.md").write_text("\n".join(md))

    body = [f"<h1>mechfmu validate: <span class={'pass' if ok else 'fail'}>{'PASS' if ok else 'FAIL'}</span></h1>",
            f"<p>{html.escape(summary.replace('**', ''))}. {html.escape(versions_text(header))}, "
            f"Python {html.escape(header['python'])}.</p>",
            f"<p class=legend>{html.escape(LEGEND)}</p>", _html_table(rows), "<h2>Platforms</h2><ul>",
            *[f"<li>{html.escape(line)}</li>" for line in platform_lines(rows)], "</ul>"]
    for entry in cases:
        body += [f"<h2 id=\"{entry['anchor']}\">{html.escape(entry['fmu'])}: {html.escape(entry['case'])}</h2>"]
        if entry.get("description"):
            body += [f"<p>{html.escape(entry['description'])}</p>"]
        body += [f"<p class=settings>Settings: {html.escape(entry['settings'])}</p>",
                 f"<img src=\"{html.escape(entry['png'])}\" alt=\"{html.escape(entry['fmu'])} {html.escape(entry['case'])}\">"]
    style = ("body{font-family:system-ui,sans-serif;max-width:72rem;margin:2rem auto;padding:0 1rem;color:#1b1f24}"
             "table{border-collapse:collapse;font-size:.9em}td,th{border:1px solid #d0d7de;padding:.2rem .5rem}"
             "th{background:#f6f8fa}td.num{text-align:right;font-variant-numeric:tabular-nums}"
             ".pass{color:#1a7f37;font-weight:600}.fail{color:#cf222e;font-weight:600}.skip{color:#9a6700}"
             "img{max-width:100%;border:1px solid #d0d7de}.legend,.settings{color:#57606a;font-size:.92em}")
    (directory / "index.html").write_text(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>mechfmu validate</title>"
        f"<style>{style}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")
