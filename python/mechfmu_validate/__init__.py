"""mechfmu_validate: validation of FMI 2.0 and FMI 3.0 FMUs, what ``mechfmu validate`` runs.

For each FMU: FMPy's ``validate_fmu`` and mechfmu's stricter checks (:mod:`.checks`); the
mechanism's reference cases, declared once in ``<crate>/validation/cases.py`` with
:class:`mechfmu_validate.case.Case`, under each importer of the registry
(:mod:`.importers`, one module each, declaring what :mod:`.importer` asks), in Co-Simulation
and in Model Exchange (:mod:`.model_exchange`); the same cases on the mechanism's FMI 3.0 FMU
(:mod:`.target`: the version a value; its array elements named by :mod:`.arrays`); a table,
an exit status, and optionally a report with one plot per case (:mod:`.report`) and the
validation tables of ``docs/validation.md`` (:mod:`.validation_tables`). The same
cases are what ``tests/python/test_cases.py``, ``test_model_exchange.py`` and ``test_fmi3.py``
run.

Command line (what ``mechfmu validate`` runs, in the venv where ``python/pyproject.toml``
installs this package)::

    python -m mechfmu_validate fmus/Oscillator.fmu --cases Oscillator=fmus/oscillator/validation/cases.py \\
        [--report DIR] [--json FILE] [--readme DIR] [--case TEXT]
    python -m mechfmu_validate references Oscillator=fmus/oscillator/validation/cases.py
"""

from .case import Case, Result, evaluate, step_input

__all__ = ["Case", "Result", "evaluate", "step_input"]
