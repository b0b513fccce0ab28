"""Timing shared by the benchmark scripts: medians of repeats, never single runs."""

from __future__ import annotations

import json
import statistics
import subprocess
import time
from collections.abc import Callable


def median_seconds(function: Callable[[], object], repeats: int, *, warm_up: bool = False) -> float:
    """Median wall time of ``repeats`` calls [s]; one untimed call first with ``warm_up``."""
    if warm_up:
        function()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def run_peer(python: str, script: str, *arguments: str) -> dict | None:
    """Run a peer's benchmark ``script`` with ``python`` (its own environment) and return
    the JSON object on its last line of output; None, saying why, when it cannot run
    (the peer is not installed, or it failed)."""
    done = subprocess.run(
        [python, "-W", "ignore", "-c", script, *arguments],
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        print(f"peer not run: {done.stderr.strip().splitlines()[-1:]}")
        return None
    return json.loads(done.stdout.strip().splitlines()[-1])
