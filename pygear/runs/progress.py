"""A small progress bar on standard error for long loops (no dependency)."""

from __future__ import annotations

import sys
import time

__all__ = ["ProgressBar"]


class ProgressBar:
    """Callable ``progress(done, total)`` that draws a bar on stderr.

    Parameters
    ----------
    label : str
        What is progressing.
    enabled : bool
        Draw nothing when False (``--quiet`` or JSON output).
    """

    def __init__(self, label: str, enabled: bool = True) -> None:
        self.label = label
        self.enabled = enabled
        self.start = time.perf_counter()
        self.last_draw = 0.0

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if done < total and now - self.last_draw < 0.1:
            return
        self.last_draw = now
        width = 30
        filled = int(width * done / max(total, 1))
        elapsed = now - self.start
        remaining = elapsed / done * (total - done) if done else float("nan")
        sys.stderr.write(
            f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
            f"{elapsed:.1f} s elapsed, {remaining:.1f} s left"
        )
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()
