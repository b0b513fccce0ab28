"""Progress of long loops on standard error (no dependency).

On a terminal a bar is redrawn in place (``\\r`` frames, at most ten a second); when
standard error is a file or a pipe (a log, a batch job's output) each report is a plain
line, at most one every :data:`LOG_INTERVAL` seconds, and the last one when the loop
ends, so logs hold no carriage returns.  Nothing is drawn with ``pygear -q``, which
leaves the ``pygear`` logger errors only.
"""

from __future__ import annotations

import logging
import sys
import time

__all__ = ["LOG_INTERVAL", "ProgressBar", "progress_wanted"]

LOG_INTERVAL = 5.0
"""Least time between two progress lines written to a file or a pipe [s]."""

_TERMINAL_INTERVAL = 0.1
"""Least time between two redraws of the bar on a terminal [s]."""


def progress_wanted() -> bool:
    """False under ``pygear -q``: the ``pygear`` logger shows errors only."""
    return logging.getLogger("pygear").isEnabledFor(logging.WARNING)


def _on_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # no stream, or a closed one
        return False


class ProgressBar:
    """Callable ``progress(done, total)`` that reports on stderr.

    Parameters
    ----------
    label : str
        What is progressing.
    enabled : bool
        Report nothing when False (``--json`` output); ``pygear -q`` silences it too.
    log_interval : float
        Least time between two lines when stderr is not a terminal [s].
    """

    def __init__(self, label: str, enabled: bool = True, log_interval: float = LOG_INTERVAL):
        self.label = label
        self.enabled = enabled
        self.log_interval = log_interval
        self.start = time.perf_counter()
        self.last_draw = 0.0
        self.last_line = self.start

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled or not progress_wanted():
            return
        now = time.perf_counter()
        finished = done >= total
        elapsed = now - self.start
        remaining = elapsed / done * (total - done) if done else float("nan")
        if not _on_terminal():
            if not finished and now - self.last_line < self.log_interval:
                return
            self.last_line = now
            if finished:
                line = f"{self.label}: {done}/{total} done in {elapsed:.1f} s"
            else:
                line = (
                    f"{self.label}: {done}/{total} ({100 * done / max(total, 1):.0f} %), "
                    f"{elapsed:.1f} s elapsed, {remaining:.1f} s left"
                )
            sys.stderr.write(line + "\n")
            sys.stderr.flush()
            return
        if not finished and now - self.last_draw < _TERMINAL_INTERVAL:
            return
        self.last_draw = now
        width = 30
        filled = int(width * done / max(total, 1))
        sys.stderr.write(
            f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
            f"{elapsed:.1f} s elapsed, {remaining:.1f} s left"
        )
        if finished:
            sys.stderr.write("\n")
        sys.stderr.flush()
