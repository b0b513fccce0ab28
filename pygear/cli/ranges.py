"""``START:STOP:COUNT`` ranges of the command line (speeds, frequencies), checked before
any work with one line naming the flag and the rule."""

from __future__ import annotations

import math

from ..errors import CaseError

__all__ = ["MAX_COUNT", "parse_range"]

MAX_COUNT = 100_000
"""Most points one range holds."""


def parse_range(
    text: str, flag: str = "--speeds", *, unit: str = "rpm", single: bool = False
) -> tuple[float, float, int]:
    """``START:STOP:COUNT`` as (start, stop, count).

    Parameters
    ----------
    text : str
        What the user typed.
    flag : str
        The option, for messages.
    unit : str
        Unit of START and STOP, for messages.
    single : bool
        Accept one point (COUNT 1 with START = STOP) and require 0 < START, as a
        steady state over speed does; otherwise START < STOP and COUNT >= 2.

    Raises
    ------
    CaseError
        Naming ``flag`` and the rule it breaks.
    """
    lowest = 1 if single else 2
    bounds = "0 < START <= STOP" if single else "START < STOP"
    rule = f"{flag} must read START:STOP:COUNT ({unit}, {bounds}, a whole COUNT >= {lowest})"
    parts = str(text).split(":")
    if len(parts) != 3:
        raise CaseError(f"{rule} (got {text!r})")
    try:
        start, stop, count_value = (float(p) for p in parts)
    except ValueError:
        raise CaseError(f"{rule} (got {text!r})") from None
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise CaseError(f"{flag} START and STOP must be finite numbers (got {text!r})")
    if single and not 0 < start <= stop:
        raise CaseError(f"{flag} START and STOP must satisfy {bounds} (got {text!r})")
    if not single and not start < stop:
        raise CaseError(f"{flag} START must be below STOP (got {text!r})")
    if not (math.isfinite(count_value) and count_value == int(count_value)):
        raise CaseError(f"{flag} COUNT must be a whole number >= {lowest} (got {parts[2]!r})")
    count = int(count_value)
    if count < lowest:
        raise CaseError(f"{flag} COUNT must be a whole number >= {lowest} (got {parts[2]!r})")
    if count > MAX_COUNT:
        raise CaseError(f"{flag} COUNT may be at most {MAX_COUNT} (got {count})")
    if count == 1 and start != stop:
        raise CaseError(f"{flag} COUNT 1 needs START = STOP (got {text!r})")
    if count > 1 and start == stop:
        raise CaseError(f"{flag} START must be below STOP for COUNT > 1 (got {text!r})")
    return start, stop, count
