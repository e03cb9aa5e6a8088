"""What the ground-station scripts share on their command line: ``--connection``, ``--timeout``
and the exit statuses (0 success, 1 `GcsError` as ``error: ...`` on stderr, 2 `UsageError`)."""
from __future__ import annotations

import argparse
import sys
from typing import Callable, NoReturn

from .errors import GcsError, UsageError
from .link import DEFAULT_CONNECTION, DEFAULT_TIMEOUT


def add_common_args(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Adds ``--connection`` and ``--timeout`` to `parser`; returns it."""
    parser.add_argument("--connection", default=DEFAULT_CONNECTION,
                        help=f"pymavlink connection string (default {DEFAULT_CONNECTION}, where `rotorpilot run` "
                             "sends its GCS telemetry)")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                        help=f"seconds to wait for the autopilot's heartbeat and for each reply (default "
                             f"{DEFAULT_TIMEOUT:g})")
    return parser


def parser(description: str) -> argparse.ArgumentParser:
    """An ArgumentParser with ``--connection`` and ``--timeout``."""
    return add_common_args(argparse.ArgumentParser(description=description,
                                                   formatter_class=argparse.RawDescriptionHelpFormatter))


def script_main(fn: Callable[[], int | None]) -> NoReturn:
    """Runs `fn()` and exits: its return value (0 if None), 1 on a `GcsError` or OSError, 2 on a
    `UsageError`, 130 on Ctrl-C; errors as ``error: ...`` on stderr, without a traceback."""
    try:
        code = fn()
    except UsageError as e:
        print(f"error: {e}", file=sys.stderr, flush=True)
        sys.exit(2)
    except (GcsError, OSError) as e:
        print(f"error: {e}", file=sys.stderr, flush=True)
        sys.exit(1)
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr, flush=True)
        sys.exit(130)
    sys.exit(code or 0)
