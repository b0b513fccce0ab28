"""A gear mesh: one spring on the line of action and its single-pair law, with its
validation beside its fields."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError
from .component_rules import (
    derived_record,
    is_finite_number,
    looks_like_radians,
    require_non_negative,
    require_positive,
)
from .geometry_inputs import GEOMETRY_LAWS, LAWS
from .plausibility import warn_if_implausible

__all__ = ["MAX_CONTACT_RATIO", "Mesh"]

_finite = is_finite_number


MAX_CONTACT_RATIO = 10.0
"""Involute gears mesh with fewer than ~3 transverse (~5 total) tooth pairs; the
tooth-contact table evaluates ceil(contact_ratio) pairs per mesh and step."""


@dataclass(frozen=True)
class Mesh:
    """A gear mesh: one spring on the line of action, with its single-pair law.

    With gear geometry on both gears of the mesh (``Gear.geometry``) the stage derives
    ``pressure_angle_deg``, ``contact_ratio``, ``overlap_ratio`` and ``backlash``
    (typed values must agree: :mod:`pygear.model.geometry_inputs`).

    Parameters
    ----------
    stiffness : float or None
        Mean (synthesizing) mesh stiffness k-bar [N/m], > 0.  Derived by the laws
        ``iso6336`` and ``potential_energy`` (typing it then is an error); required
        by the others.
    pressure_angle_deg : float or None
        Transverse operating pressure angle [deg], in (0, 45); derived from gear geometry
        when left out, else required.
    contact_ratio : float or None
        Transverse contact ratio epsilon_alpha [-], > 0 and below 10, above 1 on a spur
        stage; derived from gear geometry when left out, else required.
    end_to_peak : float
        Single-pair stiffness at the ends of contact over the peak, lambda [-], in (0, 1]
        (the parabola of docs/model.md §5.2).
    stiffness_curve : tuple of float or None
        The ``tabulated`` single-pair law [-]: the shape of the stiffness of one tooth
        pair at equally spaced relative contact positions from the start (0) to the
        end of contact (``contact_ratio``, plus ``overlap_ratio`` on a helical stage),
        at least two samples, all >= 0.  Only the shape counts: the curve is scaled so
        that the mean mesh stiffness over a mesh cycle is ``stiffness``; linear
        interpolation between samples.
    law : str or None
        Single-pair law: ``parabola`` (docs/model.md §5.2), ``tabulated``
        (``stiffness_curve``), ``helical`` (contact-line length over eps_alpha +
        eps_beta), ``iso6336`` (ISO 6336-1 method B mean c_gamma_alpha b; a constant
        pair stiffness on a spur stage, the helical law on a helical one) or
        ``potential_energy`` (the pair curve of :mod:`pygear.assembly.tooth_stiffness`)
        or ``loaded_contact`` (the loaded tooth contact of the pair with its gears'
        micro-geometry at the operating load ``line_load`` times the face width,
        :mod:`pygear.assembly.loaded_contact_table`).  None: ``tabulated`` with a
        curve, ``helical`` on a helical stage, else ``parabola``.
    overlap_ratio : float or None
        Overlap ratio epsilon_beta of a helical mesh [-], >= 0 and below 10 (derived
        from geometry).  A helical
        stage needs it, typed or derived.
    line_load : float
        K_A F_t / b [N/mm] of the ``iso6336`` law, > 0 (below 100 it lowers the
        stiffness); the ``loaded_contact`` law's operating load per face width along
        the line of action.
    young_modulus, poisson_ratio : float
        Material of both gears [Pa, -], for the ``potential_energy`` law: Young's
        modulus > 0, Poisson's ratio in [0, 0.5).
    backlash : float or None
        Circumferential backlash j_wt at the working pitch circle [m], >= 0: derived from the
        geometry (centre distance and ``thickness_allowances``) when left out.  With the
        ``tooth_separation`` effect the teeth part within it (on the flank normal,
        j_wt cos(alpha_wt) cos(beta_b)) and meet again on the coast flanks; that effect
        refuses a mesh with no backlash, typed or derived; 0 is a two-sided contact.
    thickness_allowances : tuple of float
        Normal tooth thickness allowances (A_sn1, A_sn2) [m] of the mesh geometry's
        gears in its order: (sun, planet), (planet, ring) or (input, output gear);
        negative thins a tooth; each below 1 m in size.
    """

    stiffness: float | None = None
    pressure_angle_deg: float | None = None
    contact_ratio: float | None = None
    end_to_peak: float = 0.6
    stiffness_curve: tuple[float, ...] | None = None
    law: str | None = None
    overlap_ratio: float | None = None
    line_load: float = 100.0
    young_modulus: float = 206e9
    poisson_ratio: float = 0.3
    backlash: float | None = None
    thickness_allowances: tuple[float, float] = (0.0, 0.0)
    _derived: tuple = derived_record()

    def __post_init__(self) -> None:
        for name in ("stiffness_curve", "thickness_allowances"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, tuple):
                try:
                    object.__setattr__(self, name, tuple(value))
                except TypeError:
                    pass  # validate() names it

    @property
    def pressure_angle(self) -> float:
        """Pressure angle [rad]."""
        return math.radians(self.pressure_angle_deg)

    def validate(self, path: str) -> None:
        if self.law is not None and self.law not in LAWS:
            raise CaseError(
                f"{path}.law must be one of {', '.join(LAWS)} or None (got {self.law!r})"
            )
        if self.law in GEOMETRY_LAWS:
            if self.stiffness is not None:
                raise CaseError(
                    f"{path}.stiffness must be left out with law {self.law!r}, which derives it "
                    f"from the gear geometry (got {self.stiffness!r})"
                )
        elif self.stiffness is None:
            raise CaseError(
                f"{path}.stiffness must be given (or choose law 'iso6336' or "
                "'potential_energy' with gear geometry on both gears)"
            )
        else:
            require_positive(f"{path}.stiffness", self.stiffness)
            warn_if_implausible(f"{path}.stiffness", "mesh_stiffness", self.stiffness)
        for name in ("pressure_angle_deg", "contact_ratio"):
            if getattr(self, name) is None:
                raise CaseError(
                    f"{path}.{name} must be given, or derived: give both gears of the mesh a "
                    "geometry (GearGeometry)"
                )
        if not _finite(self.pressure_angle_deg) or not 0 < self.pressure_angle_deg < 45:
            raise CaseError(
                f"{path}.pressure_angle_deg must lie in (0, 45) degrees "
                f"(got {self.pressure_angle_deg!r})"
            )
        if looks_like_radians(self.pressure_angle_deg):
            raise CaseError(
                f"{path}.pressure_angle_deg must be given in degrees: "
                f"{self.pressure_angle_deg!r} looks like radians "
                f"(= {math.degrees(self.pressure_angle_deg):.4g} deg)"
            )
        require_positive(f"{path}.contact_ratio", self.contact_ratio)
        if self.contact_ratio >= MAX_CONTACT_RATIO:
            raise CaseError(
                f"{path}.contact_ratio must be below {MAX_CONTACT_RATIO:g} tooth pairs "
                f"(got {self.contact_ratio!r})"
            )
        if not _finite(self.end_to_peak) or not 0 < self.end_to_peak <= 1:
            raise CaseError(f"{path}.end_to_peak must lie in (0, 1] (got {self.end_to_peak!r})")
        if self.stiffness_curve is not None:
            curve = self.stiffness_curve
            if (
                not isinstance(curve, tuple)
                or len(curve) < 2
                or not all(_finite(c) and c >= 0 for c in curve)
                or not sum(curve) > 0
            ):
                raise CaseError(
                    f"{path}.stiffness_curve must be a sequence of at least two finite numbers "
                    f">= 0, not all zero (got {curve!r})"
                )
            if self.law not in (None, "tabulated"):
                raise CaseError(
                    f"{path}.stiffness_curve is the shape of law 'tabulated', not of law "
                    f"{self.law!r}: drop one of them"
                )
        elif self.law == "tabulated":
            raise CaseError(f"{path}.law 'tabulated' needs a stiffness_curve")
        self._validate_geometry_inputs(path)

    def _validate_geometry_inputs(self, path: str) -> None:
        """The overlap ratio, the laws' material and load, backlash and allowances."""
        if self.overlap_ratio is not None:
            require_non_negative(f"{path}.overlap_ratio", self.overlap_ratio)
            if self.overlap_ratio >= MAX_CONTACT_RATIO:
                raise CaseError(
                    f"{path}.overlap_ratio must be below {MAX_CONTACT_RATIO:g} "
                    f"(got {self.overlap_ratio!r})"
                )
        require_positive(f"{path}.line_load", self.line_load)
        require_positive(f"{path}.young_modulus", self.young_modulus)
        warn_if_implausible(f"{path}.young_modulus", "young_modulus", self.young_modulus)
        if not _finite(self.poisson_ratio) or not 0 <= self.poisson_ratio < 0.5:
            raise CaseError(
                f"{path}.poisson_ratio must lie in [0, 0.5) (got {self.poisson_ratio!r})"
            )
        if self.backlash is not None:
            require_non_negative(f"{path}.backlash", self.backlash)
        allowances = self.thickness_allowances
        if (
            not isinstance(allowances, tuple)
            or len(allowances) != 2
            or not all(_finite(a) and abs(a) < 1.0 for a in allowances)
        ):
            raise CaseError(
                f"{path}.thickness_allowances must be two lengths (A_sn1, A_sn2) in metres "
                f"(got {allowances!r})"
            )
