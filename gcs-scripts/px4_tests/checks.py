"""Catch2's CHECK and REQUIRE for the ported cases: a failed CHECK is recorded and the case goes
on; a failed REQUIRE ends it. Each failure keeps its label, the value seen and how often it
failed (a check made on every telemetry sample fails many times but is reported once)."""
from __future__ import annotations

import math


class RequireFailed(Exception):
    """A REQUIRE did not hold: the case stops here."""


class Report:
    """The failed checks of one case, in the order they first failed."""

    def __init__(self) -> None:
        self.failures: dict[str, dict] = {}

    def record(self, label: str, seen, keep: str = "first") -> None:
        """Counts a failure of `label`; keeps the first value seen, or the largest (`keep="max"`)
        or smallest (`keep="min"`) for checks made on every sample."""
        entry = self.failures.get(label)
        if entry is None:
            self.failures[label] = {"check": label, "seen": _plain(seen), "times": 1, "raw": seen}
            return
        entry["times"] += 1
        try:
            if (keep == "max" and seen > entry["raw"]) or (keep == "min" and seen < entry["raw"]):
                entry["raw"], entry["seen"] = seen, _plain(seen)
        except TypeError:
            pass

    def summary(self) -> list[str]:
        out = []
        for f in self.failures.values():
            times = f" (failed {f['times']} times; worst shown)" if f["times"] > 1 else ""
            out.append(f"{f['check']}: seen {f['seen']}{times}")
        return out


REPORT = Report()


def _plain(value):
    """A JSON-friendly rendering of a seen value (floats rounded, NaN spelled out)."""
    if isinstance(value, float):
        return "nan" if math.isnan(value) else round(value, 4)
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (int, str, bool)) or value is None:
        return value
    return str(value)


def check(ok: bool, label: str, seen=None, keep: str = "first") -> bool:
    """CHECK: records `label` with `seen` when `ok` is false; returns `ok`."""
    if not ok:
        REPORT.record(label, seen, keep)
    return bool(ok)


def require(ok: bool, label: str, seen=None) -> None:
    """REQUIRE: records and raises `RequireFailed` when `ok` is false."""
    if not ok:
        REPORT.record(label, seen)
        raise RequireFailed(label)


def approx(value, target: float) -> bool:
    """Catch2's `Approx(target)` with its defaults: within 100 float epsilons of the target, relative."""
    return value is not None and abs(value - target) <= 100 * 1.1920929e-7 * abs(target)
