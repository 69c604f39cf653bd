"""``--plot``: a swept parameter against a summary output (matplotlib, Agg, PNG).

x: ``--plot-x`` or the first design column that varies; y: ``--plot-y`` or the first
``--summary`` (else the final value of the first output). A second varying design column
with at most 10 values draws one line per value; with more (or random) ones, the points are
coloured by it. Failed cases are marked on the x axis.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _unit(md, name: str) -> str:
    base = name.rsplit("(", 1)[-1].rstrip(")") if "(" in name else name
    for v in md.modelVariables:
        if v.name == base:
            unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
            return f" [{unit}]" if unit and unit != "1" else ""
    return ""


def plot_sweep(table, plan, path: Path, x: str | None = None, y: str | None = None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names}
    design = list(plan.design.columns)
    varying = [c for c in design if len(np.unique(data[c])) > 1]
    if x is None:
        x = varying[0] if varying else design[0]
    if y is None:
        y = plan.chosen[0] if plan.chosen else plan.setup.result_columns[0]
    ok = np.isin(data["status"], ["ok", "warning"])
    others = [c for c in varying if c != x]
    group = others[0] if others else None

    fig, ax = plt.subplots(figsize=(8, 5), dpi=120)
    xs, ys = data[x], data[y]
    random_x = any(s.is_random for s in plan.specs if s.name == x)
    if group is not None:
        levels = np.unique(data[group][ok])
        if len(levels) <= 10 and not random_x:
            cmap = plt.get_cmap("viridis", max(len(levels), 2))
            for k, level in enumerate(levels):
                sel = ok & (data[group] == level)
                order = np.argsort(xs[sel], kind="stable")
                ax.plot(xs[sel][order], ys[sel][order], "o-", ms=3, lw=1.2, color=cmap(k),
                        label=f"{group} = {level:g}")
            ax.legend(fontsize=8, loc="best", ncol=2 if len(levels) > 5 else 1)
        else:
            sc = ax.scatter(xs[ok], ys[ok], c=data[group][ok], s=12, cmap="viridis")
            fig.colorbar(sc, ax=ax, label=group + _unit(plan.md, group))
    elif random_x:
        ax.scatter(xs[ok], ys[ok], s=10)
    else:
        order = np.argsort(xs[ok], kind="stable")
        ax.plot(xs[ok][order], ys[ok][order], "o-", ms=3, lw=1.2)
    n_failed = int(np.sum(~ok))
    if n_failed:
        ax.plot(xs[~ok], np.full(n_failed, 0.0), "x", color="crimson", ms=7, mew=1.5,
                transform=ax.get_xaxis_transform(), clip_on=False, label=f"failed ({n_failed})")
        ax.legend(fontsize=8, loc="best")
    ax.set_xlabel(x + _unit(plan.md, x))
    ax.set_ylabel(y + _unit(plan.md, y))
    ax.set_title(f"{plan.model}: {y} against {x} ({len(xs)} cases)")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
