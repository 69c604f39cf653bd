"""The measure of agreement of two importers' runs of one case: the largest difference,
relative to the reference importer's signal (:func:`agreement`)."""

from __future__ import annotations

import numpy as np

from .case import Result

__all__ = ["agreement"]


def agreement(a: Result, b: Result, names: list[str],
              floors: dict[str, float] | None = None) -> tuple[float, str, float, np.ndarray]:
    """Largest |a - b| / max|b| over the signals (b the reference importer), the scale of a
    signal floored by ``floors[name]`` (the case's scale: a signal that stays at zero is
    compared in absolute terms): (value, signal, time, error over time (max over signals))."""
    worst, where, when = 0.0, "", 0.0
    over_time = np.zeros_like(b.time)
    floors = floors or {}
    for name in names:
        x, y = a[name], b[name]
        if x.shape != y.shape:
            return np.inf, name, 0.0, over_time + np.inf
        scale = max(float(np.max(np.abs(y))), floors.get(name, 0.0)) or 1.0
        err = np.abs(x - y) / scale
        err = np.where(np.isfinite(err), err, np.inf)
        over_time = np.maximum(over_time, err)
        i = int(np.argmax(err))
        if err[i] > worst or not where:
            worst, where, when = float(err[i]), name, float(b.time[i])
    return worst, where, when, over_time
