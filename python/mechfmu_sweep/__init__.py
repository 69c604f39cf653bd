"""mechfmu_sweep: parameter sweeps of FMI 2.0 Co-Simulation FMUs on Dask distributed.

The command line is ``mechfmu sweep`` (or ``python -m mechfmu_sweep``); see README.md.
From Python::

    from mechfmu_sweep import main, read_results
    main(["fmus/Crane.fmu", "--param", "l=2:10:17", "--out", "crane.parquet"])
    table = read_results("crane.parquet")
"""

__all__ = ["main", "read_results"]


def main(argv=None) -> int:
    from .cli import main as _main

    return _main(argv)


def read_results(path):
    from .results import read_results as _read

    return _read(path)
