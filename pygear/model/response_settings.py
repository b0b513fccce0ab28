"""Settings of a scene's ``response`` analysis: the periodic steady state over speed.

A description only (a frozen dataclass checked by ``validate``); the balance itself is
:func:`pygear.analysis.response.forced_response`.  A case file writes, for the study
case's speed range::

    Scene("response", analyses=("response",), dof_set="planar",
          effects=("time_varying_mesh_stiffness",),
          response=Response(speeds_rpm=(100.0, 1500.0, 200)))

and with contact loss (the answer then depends on the load: give the torque)::

    Response(speeds_rpm=(700.0, 900.0, 41), harmonics=16, contact_loss=True, torque=10.0)
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import CaseError
from .components import is_finite_number

__all__ = ["MAX_BRANCH_HARMONICS", "MAX_HARMONICS", "MAX_SPEEDS", "Response"]

MAX_SPEEDS = 100_000
"""Most speeds one response computes."""

MAX_HARMONICS = 1024
"""Largest harmonic count."""

MAX_BRANCH_HARMONICS = 128
"""Largest harmonic count with contact loss: the branch's Jacobian is dense in
n_mesh (2H + 1) unknowns."""


@dataclass(frozen=True)
class Response:
    """What the ``response`` analysis of a scene computes.

    Parameters
    ----------
    speeds_rpm : tuple (start, stop, count)
        Input member speeds [rpm]: ``count`` equally spaced from ``start`` to ``stop``,
        0 < start <= stop, a whole count >= 1 (start = stop when it is 1).
    harmonics : int or "auto"
        Harmonics of the fundamental balanced: chosen per speed by ``tolerance``
        ("auto") or fixed, 0-1024 (1-128 with ``contact_loss``).
    tolerance : float
        Residual the automatic count reaches [-], 0 < tolerance < 1.
    contact_loss : bool
        Where the linear sweep separates the teeth, continue the branch with the
        backlash flank law through its folds (``<scene>_backlash.nc``).
    torque : float or None
        Drive torque on the input member [N m], > 0; None takes the scene's drive.
    stability : bool
        Floquet multipliers of every speed (and branch point).
    pin_errors : mapping of str to float
        Tangential pin position errors [m] by planet (``planetary.planet1``), as
        ``pygear response --pin-error``; a sweep varies one as
        ``scene.response.pin_errors.<planet>``.
    """

    speeds_rpm: tuple[float, float, int]
    harmonics: int | str = "auto"
    tolerance: float = 5e-3
    contact_loss: bool = False
    torque: float | None = None
    stability: bool = True
    pin_errors: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.speeds_rpm, list):
            object.__setattr__(self, "speeds_rpm", tuple(self.speeds_rpm))
        if isinstance(self.pin_errors, dict):
            object.__setattr__(self, "pin_errors", tuple(sorted(self.pin_errors.items())))

    @property
    def speeds(self) -> list[float]:
        """The speeds [rpm], equally spaced."""
        start, stop, count = self.speeds_rpm
        count = int(count)
        if count == 1:
            return [float(start)]
        return [float(start) + (float(stop) - float(start)) * i / (count - 1)
                for i in range(count)]  # fmt: skip

    def validate(self, path: str) -> None:
        rule = (f"{path}.speeds_rpm must be (start, stop, count) [rpm] with 0 < start <= stop "
                "and a whole count >= 1")  # fmt: skip
        speeds = self.speeds_rpm
        if not (isinstance(speeds, tuple) and len(speeds) == 3):
            raise CaseError(f"{rule} (got {speeds!r})")
        start, stop, count = speeds
        if not (is_finite_number(start) and is_finite_number(stop) and 0 < start <= stop):
            raise CaseError(f"{rule} (got {speeds!r})")
        if not (is_finite_number(count) and count == int(count) and 1 <= count <= MAX_SPEEDS):
            raise CaseError(f"{path}.speeds_rpm count must be a whole number 1-{MAX_SPEEDS} "
                            f"(got {count!r})")  # fmt: skip
        if (count == 1) != (start == stop):
            raise CaseError(f"{path}.speeds_rpm: start = stop exactly when count is 1 "
                            f"(got {speeds!r})")  # fmt: skip
        top = MAX_BRANCH_HARMONICS if self.contact_loss is True else MAX_HARMONICS
        low = 1 if self.contact_loss is True else 0
        if self.harmonics != "auto" and not (
            isinstance(self.harmonics, int) and not isinstance(self.harmonics, bool)
            and low <= self.harmonics <= top
        ):  # fmt: skip
            with_loss = " with contact_loss" if self.contact_loss is True else ""
            raise CaseError(f"{path}.harmonics must be 'auto' or a whole number {low}-{top}"
                            f"{with_loss} (got {self.harmonics!r})")  # fmt: skip
        if not (is_finite_number(self.tolerance) and 0 < self.tolerance < 1):
            raise CaseError(f"{path}.tolerance must be a number between 0 and 1 "
                            f"(got {self.tolerance!r})")  # fmt: skip
        for name in ("contact_loss", "stability"):
            if not isinstance(getattr(self, name), bool):
                raise CaseError(f"{path}.{name} must be True or False "
                                f"(got {getattr(self, name)!r})")  # fmt: skip
        if self.torque is not None and not (is_finite_number(self.torque) and self.torque > 0):
            raise CaseError(f"{path}.torque must be None or a finite number > 0 [N m] "
                            f"(got {self.torque!r})")  # fmt: skip
        for item in self.pin_errors if isinstance(self.pin_errors, tuple) else (None,):
            if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str)
                    and item[0] and is_finite_number(item[1])):  # fmt: skip
                raise CaseError(f"{path}.pin_errors must map planet names to finite errors [m], "
                                f"e.g. {{'planetary.planet1': 10e-9}} (got {item!r})")  # fmt: skip
