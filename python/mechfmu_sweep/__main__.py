"""``python -m mechfmu_sweep ...``: see cli.py (the guard matters: Dask's worker processes
are spawned and import the main module)."""

import sys

if __name__ == "__main__":
    from .cli import main

    sys.exit(main())
