"""The results of a sweep, written as they come: one row per case (the case number, its design
values, status, message, summaries, timing and worker), in case order, to Parquet or CSV in
batches, so a sweep of a million cases needs no more memory than a batch."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

# rows per Parquet row group / CSV write
BATCH = 65536
FAILED_SHOWN = 5


class ResultsWriter:
    """Takes rows in case order (``add``), writes them in batches, and counts the outcomes."""

    def __init__(self, design, result_columns: list[str], meta: dict[str, Any], out: Path | None,
                 keep: bool = False):
        import pyarrow as pa

        self.design = design
        self.result_columns = result_columns
        self.out = out
        self.keep = keep  # also hold the whole table (for a plot)
        self.kept: list = []
        fields = [pa.field("case", pa.int64())]
        fields += [pa.field(c, pa.float64()) for c in design.columns]
        fields += [pa.field("status", pa.string()), pa.field("message", pa.string())]
        fields += [pa.field(c, pa.float64()) for c in result_columns]
        fields += [pa.field("elapsed_s", pa.float64()), pa.field("cpu_s", pa.float64()),
                   pa.field("worker", pa.string())]
        self.schema = pa.schema(fields, metadata={"mechfmu_sweep": json.dumps(meta)})
        self.pending: list[dict[str, Any]] = []
        self.written = 0
        self.counts: dict[str, int] = {}
        self.failed: list[dict[str, Any]] = []  # the first few
        self._writer = None
        self._sink = None

    def add(self, rows: list[dict[str, Any]]) -> None:
        for r in rows:
            status = r["status"]
            self.counts[status] = self.counts.get(status, 0) + 1
            if status not in ("ok", "warning") and len(self.failed) < FAILED_SHOWN:
                self.failed.append(r)
        self.pending.extend(rows)
        if len(self.pending) >= BATCH:
            self._flush()

    @property
    def n_failed(self) -> int:
        return sum(n for s, n in self.counts.items() if s not in ("ok", "warning"))

    def _batch(self, rows: list[dict[str, Any]]):
        import pyarrow as pa

        first = self.written
        values = self.design.values[first:first + len(rows)]
        cols: list[Any] = [pa.array(np.arange(first, first + len(rows)), pa.int64())]
        cols += [pa.array(values[:, j], pa.float64()) for j in range(len(self.design.columns))]
        cols.append(pa.array([r["status"] for r in rows], pa.string()))
        cols.append(pa.array([r.get("message", "") for r in rows], pa.string()))
        for c in self.result_columns:
            cols.append(pa.array([float(r.get(c, math.nan)) for r in rows], pa.float64()))
        for c in ("elapsed_s", "cpu_s"):
            cols.append(pa.array([float(r.get(c, math.nan)) for r in rows], pa.float64()))
        cols.append(pa.array([r.get("worker", "") for r in rows], pa.string()))
        return pa.Table.from_arrays(cols, schema=self.schema)

    def _open(self):
        import pyarrow.csv as pcsv
        import pyarrow.parquet as pq

        if self.out is None:
            self._sink = sys.stdout.buffer
            return pcsv.CSVWriter(self._sink, self.schema)
        self.out.parent.mkdir(parents=True, exist_ok=True)
        if self.out.suffix.lower() == ".parquet":
            return pq.ParquetWriter(self.out, self.schema)
        return pcsv.CSVWriter(str(self.out), self.schema)

    def _flush(self) -> None:
        if not self.pending and self._writer is not None:
            return
        table = self._batch(self.pending)
        if self._writer is None:
            self._writer = self._open()
        self._writer.write_table(table)
        if self.keep:
            self.kept.append(table)
        self.written += len(self.pending)
        self.pending = []

    def close(self, meta: dict[str, Any]):
        """Writes what is left; `meta` (the settings and how the sweep ran) goes into the
        Parquet file's metadata. Returns the whole table if ``keep``, else None."""
        import pyarrow as pa

        self._flush()
        if hasattr(self._writer, "add_key_value_metadata"):
            self._writer.add_key_value_metadata({"mechfmu_sweep": json.dumps(meta)})
        self._writer.close()
        if self._sink is not None:
            self._sink.flush()
        if not self.keep:
            return None
        table = pa.concat_tables(self.kept) if self.kept else self.schema.empty_table()
        return table.replace_schema_metadata({"mechfmu_sweep": json.dumps(meta)})


def read_results(path: Path | str):
    """The results file as a pyarrow Table (for Parquet, the sweep's settings and how it ran
    in its metadata, ``mechfmu_sweep``)."""
    import pyarrow.csv as pcsv
    import pyarrow.parquet as pq

    path = Path(path)
    if path.suffix.lower() != ".parquet":
        return pcsv.read_csv(path)
    table = pq.read_table(path)
    # written when the sweep ended, after the schema's own copy from its start
    final = pq.ParquetFile(path).metadata.metadata.get(b"mechfmu_sweep")
    return table.replace_schema_metadata({"mechfmu_sweep": final}) if final else table
