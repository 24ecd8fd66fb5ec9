"""The ``--out`` file: rows appended as episodes finish, read back to resume.

The format follows the extension: ``.csv`` or ``.parquet`` (``.pq``).

* CSV is appended row by row and flushed after every batch, so whatever finished is on
  disk even if the process is killed. If a later sweep brings new columns (another
  parameter, say), the file is rewritten once with the union of columns.
* Parquet files cannot be appended to (the footer describing the row groups is written
  last), so the store keeps the rows and atomically replaces the file — write to a
  temporary sibling, then rename — at most every ``flush_every`` seconds and on close.
  A killed process therefore loses at most the last few seconds, never the file.

Rows are identified by their ``key`` column (see :func:`~puckboard.sweep.plan.episode_key`).
"""

from __future__ import annotations

import csv
import io
import json
import logging
import os
import time
from abc import ABC, abstractmethod
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["CsvStore", "ParquetStore", "ResultStore", "open_store"]

log = logging.getLogger(__name__)


class ResultStore(ABC):
    """Where a sweep's rows go; a context manager that flushes on exit."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)

    @abstractmethod
    def rows(self) -> list[dict[str, Any]]:
        """Every row in the file (as stored: CSV values are strings)."""

    @abstractmethod
    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        """Add rows; they are on disk once :meth:`flush` ran (CSV: at once)."""

    def flush(self) -> None:  # noqa: B027 - optional hook
        """Make every appended row durable."""

    def close(self) -> None:
        self.flush()

    def keys(self) -> set[str]:
        return {str(r["key"]) for r in self.rows() if r.get("key")}

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _union_columns(existing: list[str], rows: Iterable[Mapping[str, Any]]) -> list[str]:
    columns = list(existing)
    seen = set(columns)
    for row in rows:
        for name in row:
            if name not in seen:
                seen.add(name)
                columns.append(name)
    return columns


def _csv_cell(value: Any) -> Any:
    if value is None:
        return ""
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    if isinstance(value, str) and ("\n" in value or "\r" in value):
        return " ".join(value.splitlines())  # one physical line per row; see _end_last_line
    return value


class CsvStore(ResultStore):
    """Rows in a CSV file with a header line; see the module docstring."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        self._columns: list[str] = []
        if self.path.exists() and self.path.stat().st_size > 0:
            with self.path.open(newline="", encoding="utf-8") as f:
                header = next(csv.reader(f), [])
            if "key" not in header:
                raise ValueError(
                    f"{str(self.path)!r} exists but is not a sweep results file (no 'key' "
                    "column); name another file"
                )
            self._columns = header
            self._end_last_line()

    def _end_last_line(self) -> None:
        # A run killed mid-write leaves a partial last line. No field holds a line break
        # (rows are single-line by construction), so cut the file back to its last whole
        # line; the lost episode simply runs again.
        with self.path.open("rb+") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - 65536))
            tail = f.read()
            if tail.endswith(b"\n"):
                return
            cut = tail.rfind(b"\n")
            if cut < 0:
                raise ValueError(f"{self.path}: the last row is longer than 64 KiB or broken")
            f.truncate(size - len(tail) + cut + 1)
            log.warning(
                "%s: dropped an incomplete last row (a run was killed while writing)", self.path
            )

    def rows(self) -> list[dict[str, Any]]:
        if not self._columns:
            return []
        with self.path.open(newline="", encoding="utf-8") as f:
            rows = [dict(r) for r in csv.DictReader(f)]
        complete = [r for r in rows if None not in r.values() and None not in r]
        if len(complete) < len(rows):
            log.warning(
                "%s: ignoring %d incomplete row(s) (a run was killed while writing); "
                "those episodes run again",
                self.path,
                len(rows) - len(complete),
            )
        return complete

    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        rows = list(rows)
        if not rows:
            return
        columns = _union_columns(self._columns, rows)
        if self._columns and columns != self._columns:
            self._rewrite(columns)
        new_file = not self._columns
        self._columns = columns
        self.path.parent.mkdir(parents=True, exist_ok=True)
        text = io.StringIO(newline="")
        writer = csv.DictWriter(text, fieldnames=columns, restval="")
        if new_file:
            writer.writeheader()
        for row in rows:
            writer.writerow({k: _csv_cell(v) for k, v in row.items()})
        # one write per batch: a killed process leaves whole rows, not half of one
        with self.path.open("a", newline="", encoding="utf-8") as f:
            f.write(text.getvalue())
            f.flush()

    def _rewrite(self, columns: list[str]) -> None:
        old = self.rows()
        tmp = self.path.with_name(self.path.name + ".tmp")
        with tmp.open("w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=columns, restval="")
            writer.writeheader()
            writer.writerows(old)
        os.replace(tmp, self.path)


def _arrow_column(values: list[Any]) -> list[Any]:
    """Make a column Arrow can type: one Python type besides None, else strings."""
    kinds = {type(v) for v in values if v is not None}
    if kinds <= {int, float}:
        return values
    if len(kinds) <= 1:
        return values
    return [None if v is None else str(v) for v in values]


class ParquetStore(ResultStore):
    """Rows in a Parquet file, rewritten atomically; see the module docstring."""

    def __init__(self, path: str | os.PathLike[str], flush_every: float = 2.0) -> None:
        super().__init__(path)
        try:
            import pyarrow.parquet as pq
        except ImportError as exc:
            raise ImportError(
                "Parquet output needs pyarrow: pip install 'puckboard[dask]' (or use a .csv file)"
            ) from exc
        self.flush_every = flush_every
        self._rows: list[dict[str, Any]] = []
        self._dirty = False
        self._last_flush = time.monotonic()
        if self.path.exists():
            table = pq.read_table(self.path)
            if "key" not in table.column_names:
                raise ValueError(
                    f"{str(self.path)!r} exists but is not a sweep results file (no 'key' "
                    "column); name another file"
                )
            self._rows = table.to_pylist()

    def rows(self) -> list[dict[str, Any]]:
        return [dict(r) for r in self._rows]

    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        added = [dict(r) for r in rows]
        if not added:
            return
        self._rows.extend(added)
        self._dirty = True
        if time.monotonic() - self._last_flush >= self.flush_every:
            self.flush()

    def flush(self) -> None:
        if not self._dirty:
            return
        import pyarrow as pa
        import pyarrow.parquet as pq

        columns = _union_columns([], self._rows)
        data = {c: _arrow_column([r.get(c) for r in self._rows]) for c in columns}
        table = pa.table(data)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(self.path.name + ".tmp")
        pq.write_table(table, tmp)
        os.replace(tmp, self.path)
        self._dirty = False
        self._last_flush = time.monotonic()
        log.debug("wrote %d rows to %s", len(self._rows), self.path)


def open_store(path: str | os.PathLike[str]) -> ResultStore:
    """A store for ``path``, chosen by its extension (``.csv``, ``.parquet`` or ``.pq``)."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        return CsvStore(path)
    if suffix in (".parquet", ".pq"):
        return ParquetStore(path)
    raise ValueError(
        f"{str(path)!r}: use a .csv or .parquet file name (.parquet needs pyarrow: pip install "
        "'puckboard[dask]')"
    )
