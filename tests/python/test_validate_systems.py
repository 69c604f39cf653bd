"""`mechfmu validate` end to end on the system FMUs (a system compiled into one FMU): the same
checks as the mechanisms' in test_validate.py, in a file of its own so that pytest-xdist runs
the two on two cores."""

from __future__ import annotations

from mechanisms import mechanisms
from test_validate import assert_validate_passes


def test_validate_passes_on_every_system_fmu_and_writes_the_report(tmp_path):
    assert_validate_passes([m.model for m in mechanisms() if m.system], tmp_path)
