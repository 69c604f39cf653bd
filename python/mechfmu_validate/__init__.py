"""mechfmu_validate: validation of FMI 2.0 FMUs, what ``mechfmu validate`` runs.

For each FMU: FMPy's ``validate_fmu`` and mechfmu's stricter checks (:mod:`.checks`); the
mechanism's reference cases, declared once in ``<crate>/validation/cases.py`` with
:class:`mechfmu_validate.case.Case`, under FMPy's ``simulate_fmu``, libcosim and the fmi crate
in Co-Simulation (:mod:`.importers`), and in Model Exchange (:mod:`.model_exchange`); a table,
an exit status, and optionally a report with one plot per case (:mod:`.report`). The same
cases are what ``tests/python/test_cases.py`` and ``test_model_exchange.py`` run.

Command line (what ``mechfmu validate`` runs, in the venv where ``python/pyproject.toml``
installs this package)::

    python -m mechfmu_validate fmus/Oscillator.fmu --cases Oscillator=fmus/oscillator/validation/cases.py \\
        [--report DIR] [--json FILE] [--readme DIR] [--case TEXT]
    python -m mechfmu_validate references Oscillator=fmus/oscillator/validation/cases.py
"""

from .case import Case, Result, evaluate, step_input

__all__ = ["Case", "Result", "evaluate", "step_input"]
