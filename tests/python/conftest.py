"""Fixtures for the FMPy test suite (helpers live in fmutest.py).

    def test_something(fmu):
        path = fmu("Oscillator")          # fmus/Oscillator.fmu, fails if not built

    def test_log(slave):
        with slave("Oscillator") as s:    # fmpy FMU2Slave, raw statuses, captured log
            ...
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # `import refs`, `import fmutest`

import fmutest  # noqa: E402


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return fmutest.REPO_ROOT


@pytest.fixture
def fmu():
    """fmu(name) -> Path of fmus/<name>.fmu; a missing FMU fails the test (no skip)."""
    return fmutest.fmu_path


@pytest.fixture
def slave():
    """slave(name, **kw) -> fmutest.Slave (instantiated); every instance is freed at teardown."""
    made: list[fmutest.Slave] = []

    def make(name: str, **kwargs) -> fmutest.Slave:
        s = fmutest.Slave(fmutest.fmu_path(name), **kwargs)
        made.append(s)
        return s

    yield make
    for s in made:
        s.free()


@pytest.fixture
def log_mark():
    """A fresh fmutest.LogMark: the FMU messages logged during the test."""
    return fmutest.LogMark()


#: the files that take longest, longest first: run first, so that under pytest-xdist
#: (scripts/test: one worker per core, a file to a worker, files in this order:
#: --no-loadscope-reorder) no core is left with one of them at the end while the others idle
LONGEST_FIRST = ("test_new_mechanism.py", "test_install.py", "test_validate.py", "test_validate_systems.py",
                 "test_fmi3.py", "test_systems.py", "test_cross_check.py", "test_model_exchange.py", "test_platforms.py")


def pytest_collection_modifyitems(session, config, items):
    def rank(item) -> int:
        name = item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: a file's tests keep their order


def pytest_sessionfinish(session, exitstatus):
    fmutest.cleanup_extracted()


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """Show the achieved errors even under -q (the tables are in target/test-figures/)."""
    lines = fmutest.figures_summary()
    if lines:
        terminalreporter.write_sep("-", "achieved errors against the references")
        for line in lines:
            terminalreporter.write_line(line)
