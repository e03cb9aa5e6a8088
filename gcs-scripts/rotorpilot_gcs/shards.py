"""The pure part of a sweep run in shards (`rotorpilot_gcs.campaign`): cutting the runs into
shards, checking what a shard returned, and merging the shards' tables into the binary's column
order. No processes, no Ray; pyarrow is imported where a table is handled."""
from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Iterable, Sequence

from .errors import UsageError

#: Shards per CPU of the cluster when neither ``--shards`` nor ``--shard-size`` is given: enough
#: that a slow shard does not leave the other CPUs idle at the end.
SHARDS_PER_CPU = 4
#: The columns before the axes, and those between the axes and the metrics (the binary's schema).
LEADING_COLUMNS = ("run", "point", "seed")
STATUS_COLUMNS = ("status", "error")


class ShardFailure(ValueError):
    """What a shard's task returned is not its runs' table (the message says why)."""


@dataclass(frozen=True)
class Shard:
    """Runs `start` … `stop` − 1 of the sweep (indices into the whole sweep), the `index`-th shard."""

    index: int
    start: int
    stop: int

    @property
    def runs(self) -> str:
        """The binary's ``--runs`` value, ``A..B`` (end exclusive)."""
        return f"{self.start}..{self.stop}"

    def __len__(self) -> int:
        return self.stop - self.start

    def __str__(self) -> str:
        return f"shard {self.index} (runs {self.runs})"


def default_shard_count(runs: int, cpus: float) -> int:
    """About `SHARDS_PER_CPU` shards per CPU, at most one per run, at least one."""
    return max(1, min(runs, SHARDS_PER_CPU * max(1, int(cpus))))


def split_runs(runs: int, shards: int | None = None, shard_size: int | None = None) -> list[Shard]:
    """Runs 0 … `runs` − 1 cut into contiguous shards: `shards` of them as equal as can be (the
    first ones one run longer), or shards of `shard_size` runs (the last one shorter). Never an
    empty shard: more shards than runs gives one run each. `UsageError` for a count or size < 1,
    or both given."""
    if runs < 1:
        raise UsageError(f"the sweep has {runs} runs")
    if shards is not None and shard_size is not None:
        raise UsageError("give --shards or --shard-size, not both")
    if shard_size is not None:
        if shard_size < 1:
            raise UsageError(f"--shard-size is {shard_size}; it must be at least 1")
        bounds = list(range(0, runs, shard_size)) + [runs]
    else:
        count = 1 if shards is None else shards
        if count < 1:
            raise UsageError(f"--shards is {count}; it must be at least 1")
        count = min(count, runs)
        base, extra = divmod(runs, count)
        bounds = [0]
        for i in range(count):
            bounds.append(bounds[-1] + base + (1 if i < extra else 0))
    return [Shard(i, a, b) for i, (a, b) in enumerate(zip(bounds, bounds[1:]))]


def axis_fields(plan: dict[str, Any]) -> list[str]:
    """The swept fields of a plan, in axis order (each axis is an object with ``field``, or the
    field itself)."""
    fields = []
    for axis in plan.get("axes") or []:
        fields.append(str(axis["field"]) if isinstance(axis, dict) else str(axis))
    return fields


def canonical_columns(names: Iterable[str], axes: Sequence[str]) -> list[str]:
    """`names` in the binary's column order: run, point, seed, the `axes` in their order, status,
    error, then every other column (the metrics) sorted by name. Columns of that order missing
    from `names` are left out."""
    present = list(names)
    fixed = [*LEADING_COLUMNS, *axes, *STATUS_COLUMNS]
    head = [name for name in fixed if name in present]
    return head + sorted(name for name in present if name not in fixed)


def merge_tables(tables: Sequence[Any], axes: Sequence[str]) -> Any:
    """One pyarrow table of the shards' `tables`: concatenated (a column missing from a shard,
    as a metric that is null on all its runs, becomes nulls there), columns in
    `canonical_columns` order, rows sorted by run."""
    import pyarrow as pa

    if not tables:
        raise ValueError("no tables to merge")
    try:
        table = pa.concat_tables(tables, promote_options="default")
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        # A column typed differently in two shards (an int64 metric against a double): widen it.
        table = pa.concat_tables(tables, promote_options="permissive")
    table = table.select(canonical_columns(table.column_names, axes))
    for name in STATUS_COLUMNS:  # strings by the schema, even where every row has none
        if name in table.column_names and pa.types.is_null(table.schema.field(name).type):
            table = table.set_column(table.column_names.index(name), name, table.column(name).cast(pa.string()))
    return table.sort_by("run") if "run" in table.column_names else table


def shard_table(shard: Shard, result: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
    """The table of a shard's `result` (`run_shard`) and the binary's summary; `ShardFailure`
    naming what is wrong: a non-zero exit, no summary, an unreadable table, not the shard's
    runs."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    code = result.get("returncode")
    if code != 0:
        tail = (result.get("stderr") or "").strip().splitlines()
        why = tail[-1] if tail else "no message"
        raise ShardFailure(why if code is None else f"exit status {code}: {why}")
    try:
        summary = json.loads(result.get("stdout") or "")
    except ValueError:
        raise ShardFailure(f"no JSON summary on stdout: {result.get('stdout', '')[:200]!r}") from None
    if "parquet" not in result:
        raise ShardFailure("exit status 0 but no results.parquet")
    try:
        table = pq.read_table(pa.BufferReader(result["parquet"]))
    except pa.ArrowException as e:
        raise ShardFailure(f"results.parquet unreadable: {e}") from None
    runs = table.column("run").to_pylist() if "run" in table.column_names else None
    if runs is None or sorted(runs) != list(range(shard.start, shard.stop)):
        raise ShardFailure(f"results.parquet holds {table.num_rows} rows, not runs {shard.runs}")
    return table, summary
