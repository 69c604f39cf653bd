"""Loading a mechanism's ``validation/cases.py``.

The file is imported as a module of its own (every crate's is called ``cases.py``); it must
define ``CASES``, a list of :class:`~mechfmu_validate.case.Case`. While it loads, its own
folder and mechfmu's independent reference models (``tests/python``, importable as ``refs``)
are on ``sys.path``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from .case import Case

__all__ = ["load_cases", "REFS_DIR", "default_case", "reference_case"]

#: mechfmu's independent reference solutions (the package ``refs``)
REFS_DIR = Path(__file__).resolve().parents[2] / "tests" / "python"

_loaded: dict[Path, list[Case]] = {}


def load_cases(path: str | Path, model: str = "") -> list[Case]:
    """The ``CASES`` of a cases file (loaded once per process)."""
    path = Path(path).resolve()
    if path in _loaded:
        return _loaded[path]
    for extra in (REFS_DIR, path.parent):
        if extra.is_dir() and str(extra) not in sys.path:
            sys.path.insert(0, str(extra))
    name = f"mechfmu_cases_{model or path.parent.parent.name}".replace("-", "_")
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    cases = getattr(module, "CASES", None)
    if not isinstance(cases, (list, tuple)) or not all(isinstance(c, Case) for c in cases):
        raise TypeError(f"{path} must define CASES, a list of mechfmu_validate.case.Case")
    names = [c.name for c in cases]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ValueError(f"{path}: duplicate case names {dup}")
    if sum(c.default_experiment for c in cases) > 1:
        raise ValueError(f"{path}: more than one case is marked default_experiment")
    if sum(bool(c.reference_files) for c in cases) > 1:
        raise ValueError(f"{path}: more than one case names reference_files")
    _loaded[path] = list(cases)
    return _loaded[path]


def default_case(cases: list[Case]) -> Case | None:
    return next((c for c in cases if c.default_experiment), None)


def reference_case(cases: list[Case]) -> Case | None:
    """The case the reference files come from: the one naming ``reference_files``, else the
    default experiment's."""
    return next((c for c in cases if c.reference_files), None) or default_case(cases)
