"""Rating data of a case: materials, required safeties, life, duty cycle and bearings.

A case file declares what ``pygear rate`` needs beside the geometry pygear already has,
in a module-level ``rating = Rating(...)`` next to ``case = Case(...)``:

* :class:`Material` per gear (ISO 6336-5 endurance limits, hardness, roughness),
  either typed or from :func:`iso6336_5_material` (quality grades ML, MQ, ME);
* the application factor, required safeties S_Hmin and S_Fmin, the design life and
  the rated input torque and speed it is rated at;
* any load factor the user knows better than the standard's methods (K_gamma per
  stage, K_v, K_Hbeta, K_Halpha per mesh): given factors are used as they are, and
  the rating output says which were given and which computed;
* a :class:`DutyCycle` (input torque bins x hours, ISO 6336-6's load spectrum);
* :class:`RollingBearingData` per bearing (ISO 281 catalogue data).

Units: SI (Pa, m, N, N m, rpm for speeds, hours for time).  Every rule is checked when
the object is built; a broken rule raises :class:`~pygear.errors.CaseError` naming the
parameter and the rule.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

from ..errors import CaseError

__all__ = [
    "MATERIAL_KINDS",
    "QUALITY_GRADES",
    "DutyCycle",
    "Material",
    "Rating",
    "RollingBearingData",
    "iso6336_5_material",
    "load_rating",
]

MATERIAL_KINDS = ("case_carburized", "nitrided", "through_hardened")
"""Heat treatments the rating knows (ISO 6336-5 material groups Eh, NT/NV, V)."""

QUALITY_GRADES = ("ML", "MQ", "ME")
"""ISO 6336-5 material quality grades: ML modest, MQ normal (industrial), ME high."""

# ISO 6336-5:2016 endurance limits [MPa].  Case-carburized wrought steel (Eh) and
# nitrided steel (NT) at their usual surface hardness are single values per grade;
# through-hardened alloy steel (V) follows sigma = A x + B with x the hardness HV.
_SURFACE_HARDENED = {
    # kind: {grade: (sigma_hlim, sigma_flim)}
    "case_carburized": {"ML": (1300.0, 312.0), "MQ": (1500.0, 425.0), "ME": (1650.0, 525.0)},
    "nitrided": {"ML": (1125.0, 270.0), "MQ": (1250.0, 420.0), "ME": (1450.0, 468.0)},
}
_THROUGH_HARDENED = {
    # grade: ((A, B) contact, (A, B) root), hardness in HV
    "ML": ((0.963, 283.0), (0.250, 108.0)),
    "MQ": ((0.925, 360.0), (0.240, 163.0)),
    "ME": ((0.838, 432.0), (0.283, 202.0)),
}
_SLIP_LAYER = {"case_carburized": 0.0030, "nitrided": 0.1005, "through_hardened": 0.0194}
"""Slip-layer thickness rho' [mm] of ISO 6336-3's Y_delta rel T (method B); the
through-hardened value is the one for sigma_0.2 = 800 MPa."""


def _positive(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(f"{name} must be a number (got {value!r})")
    if not (math.isfinite(value) and value > 0.0):
        raise CaseError(f"{name} must be a positive finite number (got {value!r})")
    return float(value)


def _factor(name: str, value: object) -> None:
    """A given load or life factor: None (computed) or a finite number >= 1."""
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CaseError(f"{name} must be a finite number or None (got {value!r})")
    if value < 1.0:
        raise CaseError(f"{name} must be >= 1 (a load factor never lowers the load; got {value})")


@dataclass(frozen=True)
class Material:
    """A gear material and its surface (ISO 6336-5).

    Parameters
    ----------
    name : str
        Designation, e.g. "18CrNiMo7-6".
    kind : str
        One of :data:`MATERIAL_KINDS`.
    sigma_hlim : float
        Endurance limit for contact stress [Pa].
    sigma_flim : float
        Nominal stress number for bending [Pa] (sigma_FE = Y_ST sigma_flim, Y_ST = 2).
    grade : str
        Quality grade ML, MQ or ME (reported; the limits above are what is used).
    hardness_hb : float or None
        Brinell hardness of a through-hardened gear (the work-hardening factor Z_W of a
        soft gear meshing with a hardened one) [HBW]; None for surface-hardened gears.
    young_modulus, poisson_ratio : float
        Elastic constants (Z_E) [Pa], [-].
    flank_roughness_rz, root_roughness_rz : float
        Mean peak-to-valley roughness R_z of flank and root [m].
    slip_layer : float or None
        rho' of Y_delta rel T [m]; None takes ISO 6336-3's value for the kind.
    """

    name: str
    kind: str
    sigma_hlim: float
    sigma_flim: float
    grade: str = "MQ"
    hardness_hb: float | None = None
    young_modulus: float = 206e9
    poisson_ratio: float = 0.3
    flank_roughness_rz: float = 4.8e-6
    root_roughness_rz: float = 20e-6
    slip_layer: float | None = None

    def __post_init__(self) -> None:
        self.validate("material")

    def validate(self, path: str) -> None:
        """Raise CaseError naming the first parameter that breaks its rule."""
        if self.kind not in MATERIAL_KINDS:
            raise CaseError(f"{path}.kind must be one of {MATERIAL_KINDS} (got {self.kind!r})")
        if self.grade not in QUALITY_GRADES:
            raise CaseError(f"{path}.grade must be one of {QUALITY_GRADES} (got {self.grade!r})")
        for name in ("sigma_hlim", "sigma_flim", "young_modulus"):
            _positive(f"{path}.{name}", getattr(self, name))
        if self.sigma_hlim < 1e6:
            raise CaseError(
                f"{path}.sigma_hlim must be in Pa (got {self.sigma_hlim}; MPa times 1e6)"
            )
        if self.sigma_flim < 1e6:
            raise CaseError(
                f"{path}.sigma_flim must be in Pa (got {self.sigma_flim}; MPa times 1e6)"
            )
        if not 0.0 <= self.poisson_ratio < 0.5:
            raise CaseError(f"{path}.poisson_ratio must be in [0, 0.5) (got {self.poisson_ratio})")
        for name in ("flank_roughness_rz", "root_roughness_rz"):
            value = _positive(f"{path}.{name}", getattr(self, name))
            if value > 1e-4:
                raise CaseError(f"{path}.{name} must be in m (got {value}; 1 um is 1e-6)")
        if self.hardness_hb is not None:
            hardness = _positive(f"{path}.hardness_hb", self.hardness_hb)
            if not 100.0 <= hardness <= 700.0:
                raise CaseError(f"{path}.hardness_hb must be in 100..700 HB (got {hardness})")
        if self.slip_layer is not None:
            _positive(f"{path}.slip_layer", self.slip_layer)

    @property
    def slip_layer_mm(self) -> float:
        """rho' [mm] (ISO 6336-3 table value unless given)."""
        if self.slip_layer is not None:
            return self.slip_layer * 1e3
        return _SLIP_LAYER[self.kind]


def iso6336_5_material(
    name: str, kind: str, grade: str = "MQ", hardness_hv: float | None = None, **extra: object
) -> Material:
    """A :class:`Material` with ISO 6336-5's endurance limits for ``kind`` and ``grade``.

    Case-carburized and nitrided steels take the grade's value at their usual surface
    hardness; a through-hardened steel needs ``hardness_hv`` (200..360 HV) and follows
    the standard's line sigma = A HV + B.  ``extra`` passes other Material fields.
    """
    if kind not in MATERIAL_KINDS:
        raise CaseError(f"kind must be one of {MATERIAL_KINDS} (got {kind!r})")
    if grade not in QUALITY_GRADES:
        raise CaseError(f"grade must be one of {QUALITY_GRADES} (got {grade!r})")
    if kind == "through_hardened":
        if hardness_hv is None or not 200.0 <= float(hardness_hv) <= 360.0:
            raise CaseError(
                f"hardness_hv must be in 200..360 HV for a through-hardened steel "
                f"(ISO 6336-5's range; got {hardness_hv!r})"
            )
        (a_h, b_h), (a_f, b_f) = _THROUGH_HARDENED[grade]
        limits = (a_h * hardness_hv + b_h, a_f * hardness_hv + b_f)
        extra.setdefault("hardness_hb", 0.95 * hardness_hv)  # HB ~ 0.95 HV in this range
    else:
        limits = _SURFACE_HARDENED[kind][grade]
    return Material(
        name=name, kind=kind, grade=grade, sigma_hlim=limits[0] * 1e6, sigma_flim=limits[1] * 1e6,
        **extra,
    )


@dataclass(frozen=True)
class DutyCycle:
    """A load duration distribution: input torque bins and the hours spent in each.

    Parameters
    ----------
    torque : tuple of float
        Input torque of each bin [N m] (> 0; the rated torque's direction).
    hours : tuple of float
        Hours in each bin [h] (>= 0, at least one > 0).
    speed_rpm : tuple of float or None
        Input speed of each bin [rpm]; None runs every bin at the rating's speed.
    period_h : float or None
        Hours the distribution stands for [h], when more than its bins' sum (a yearly
        spectrum of the operating hours stands for a year, idle hours included); None:
        the sum of ``hours``.
    """

    torque: tuple[float, ...]
    hours: tuple[float, ...]
    speed_rpm: tuple[float, ...] | None = None
    period_h: float | None = None

    def __post_init__(self) -> None:
        for name in ("torque", "hours", "speed_rpm"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, tuple(float(v) for v in value))
        self.validate("duty_cycle")

    def validate(self, path: str) -> None:
        """Raise CaseError naming the first parameter that breaks its rule."""
        if not self.torque:
            raise CaseError(f"{path}.torque must hold at least one bin")
        if len(self.hours) != len(self.torque):
            raise CaseError(
                f"{path}.hours must have one value per torque bin "
                f"({len(self.hours)} given for {len(self.torque)} bins)"
            )
        for k, value in enumerate(self.torque):
            _positive(f"{path}.torque[{k}]", value)
        for k, value in enumerate(self.hours):
            if not (math.isfinite(value) and value >= 0.0):
                raise CaseError(f"{path}.hours[{k}] must be finite and >= 0 (got {value})")
        if sum(self.hours) <= 0.0:
            raise CaseError(f"{path}.hours must add up to more than 0 h")
        if self.period_h is not None and not (
                math.isfinite(self.period_h) and self.period_h >= sum(self.hours) * (1 - 1e-12)):
            raise CaseError(f"{path}.period_h must be finite and at least the bins' "
                            f"{sum(self.hours):g} h (got {self.period_h})")
        if self.speed_rpm is not None:
            if len(self.speed_rpm) != len(self.torque):
                raise CaseError(f"{path}.speed_rpm must have one value per torque bin")
            for k, value in enumerate(self.speed_rpm):
                _positive(f"{path}.speed_rpm[{k}]", value)


BEARING_KINDS = ("ball", "roller")


@dataclass(frozen=True)
class RollingBearingData:
    """Catalogue data of one rolling bearing and where its load comes from (ISO 281).

    Parameters
    ----------
    name : str
        Bearing name (e.g. "PL-A").
    kind : str
        "ball" (life exponent p = 3) or "roller" (p = 10/3).
    C, C0 : float
        Basic dynamic and static load ratings [N].
    location : str
        The body it carries: "<stage>.planet" (load from the planet's two meshes, per
        planet) or any other label with ``radial_load`` and ``axial_load`` given.
    share : float
        Fraction of the body's load this bearing carries [-] (two bearings side by side
        on a planet pin: 0.5).
    radial_load, axial_load : float or None
        Loads at the rated torque [N] for a bearing whose load pygear does not derive;
        they scale linearly with the torque of a duty-cycle bin.
    e, X, Y : float
        ISO 281 factors for F_a/F_r > e (P = X F_r + Y F_a) [-].
    Y1 : float
        Y for F_a/F_r <= e (P = F_r + Y1 F_a) [-].
    speed_factor : float or None
        Bearing speed over the input speed [-]; None for a planet bearing (derived from
        the stage's kinematics).
    pitch_diameter : float
        Mean diameter d_m = (D + d)/2 [m] (viscosity ratio kappa of a_ISO).
    fatigue_load_limit : float or None
        C_u [N]; None estimates it from C0 (ISO 281 Annex B, roller or ball).
    contamination : float
        e_C of ISO 281 Table 13 [-] (0 < e_C <= 1).
    viscosity : float
        Operating kinematic viscosity nu of the lubricant [mm^2/s].
    """

    name: str
    kind: str
    C: float
    C0: float
    location: str
    share: float = 1.0
    radial_load: float | None = None
    axial_load: float | None = None
    e: float = 1e9
    X: float = 1.0
    Y: float = 0.0
    Y1: float = 0.0
    speed_factor: float | None = None
    pitch_diameter: float = 0.5
    fatigue_load_limit: float | None = None
    contamination: float = 0.5
    viscosity: float = 68.0

    def __post_init__(self) -> None:
        self.validate(f"bearings[{self.name!r}]")

    def validate(self, path: str) -> None:
        """Raise CaseError naming the first parameter that breaks its rule."""
        if self.kind not in BEARING_KINDS:
            raise CaseError(f"{path}.kind must be one of {BEARING_KINDS} (got {self.kind!r})")
        for name in ("C", "C0", "share", "pitch_diameter", "viscosity", "e", "X"):
            _positive(f"{path}.{name}", getattr(self, name))
        if self.share > 1.0:
            raise CaseError(f"{path}.share must be in (0, 1] (got {self.share})")
        if not 0.0 < self.contamination <= 1.0:
            raise CaseError(f"{path}.contamination must be in (0, 1] (got {self.contamination})")
        for name in ("Y", "Y1"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise CaseError(f"{path}.{name} must be finite and >= 0 (got {value})")
        planet = self.location.endswith(".planet")
        if not planet and self.radial_load is None:
            raise CaseError(
                f"{path}.radial_load must be given for a bearing at {self.location!r} "
                "(pygear derives the load of planet bearings, location '<stage>.planet')"
            )
        if not planet and self.speed_factor is None:
            raise CaseError(f"{path}.speed_factor must be given for a bearing off a planet")
        for name in ("radial_load", "axial_load", "fatigue_load_limit", "speed_factor"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value >= 0.0):
                raise CaseError(f"{path}.{name} must be finite and >= 0 or None (got {value})")


@dataclass(frozen=True)
class Rating:
    """What a case is rated against (ISO 6336 and ISO 281).

    Parameters
    ----------
    materials : dict of str to Material
        Per gear, named "<stage>.<member>" (sun, planet, ring; input_gear, output_gear).
    rated_torque : float
        Input torque at the rating point [N m] (the gearbox input).
    rated_speed_rpm : float
        Input speed at the rating point [rpm].
    application_factor : float
        K_A (ISO 6336-1 Annex) [-], >= 1.
    required_sh, required_sf : float
        Minimum safeties S_Hmin and S_Fmin [-].
    service_life_h : float
        Design life [h] (number of load cycles of the static rating).
    load_sharing : dict of str to float
        K_gamma per planetary stage [-]; a stage left out takes the default for its planet
        count (see :mod:`pygear.analysis.rating`), unless it has position errors.
    planet_position_errors : dict of str to tuple of float
        Per planetary stage, each planet's position error along the line of action [m]
        (> 0: ahead in the loaded sense); K_gamma then comes from the static model at the
        rated torque (:mod:`pygear.analysis.rating.load_sharing`).
    dynamic_factor, face_load_factor, transverse_load_factor : dict of str to float
        K_v, K_Hbeta and K_Halpha (= K_Falpha) per mesh [-], named "<stage>.sun_mesh",
        "<stage>.ring_mesh" or "<stage>.mesh"; a mesh left out gets the standard's method.
    face_load_from_model : bool
        K_Hbeta of the meshes ``face_load_factor`` leaves out with the shaft and bearing
        mismatch f_sh from the case's static deflection under the rated torque
        (:mod:`pygear.analysis.rating.deflection`; meaningful where the model holds the
        supports' tilt stiffness, a drivetrain case); False: f_sh = 0.
    accuracy_grade : int
        ISO 1328-1 accuracy grade Q (pitch and profile deviations of K_v, K_Halpha).
    oil_viscosity_40 : float
        Kinematic viscosity of the oil at 40 degC [mm^2/s] (Z_L).
    duty_cycle : DutyCycle or None
        Load duration distribution for ISO 6336-6 and the ISO 281 mean load.
    bearings : tuple of RollingBearingData
        Bearings to rate.
    """

    materials: dict[str, Material]
    rated_torque: float
    rated_speed_rpm: float
    application_factor: float = 1.0
    required_sh: float = 1.0
    required_sf: float = 1.0
    service_life_h: float = 20000.0
    load_sharing: dict[str, float] = field(default_factory=dict)
    planet_position_errors: dict[str, tuple[float, ...]] = field(default_factory=dict)
    dynamic_factor: dict[str, float] = field(default_factory=dict)
    face_load_factor: dict[str, float] = field(default_factory=dict)
    transverse_load_factor: dict[str, float] = field(default_factory=dict)
    face_load_from_model: bool = False
    accuracy_grade: int = 6
    oil_viscosity_40: float = 220.0
    duty_cycle: DutyCycle | None = None
    bearings: tuple[RollingBearingData, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "bearings", tuple(self.bearings))
        self.validate()

    def validate(self) -> None:
        """Raise CaseError naming the first parameter that breaks its rule."""
        if not isinstance(self.materials, dict) or not self.materials:
            raise CaseError("rating.materials must map gear names to Material objects")
        for gear, material in self.materials.items():
            if not isinstance(material, Material):
                raise CaseError(f"rating.materials[{gear!r}] must be a Material")
        _positive("rating.rated_torque", self.rated_torque)
        _positive("rating.rated_speed_rpm", self.rated_speed_rpm)
        _factor("rating.application_factor", self.application_factor)
        for name in ("required_sh", "required_sf"):
            _positive(f"rating.{name}", getattr(self, name))
        _positive("rating.service_life_h", self.service_life_h)
        _positive("rating.oil_viscosity_40", self.oil_viscosity_40)
        for table in ("load_sharing", "dynamic_factor", "face_load_factor",
                      "transverse_load_factor"):
            for key, value in getattr(self, table).items():
                _factor(f"rating.{table}[{key!r}]", value)
        for stage, errors in self.planet_position_errors.items():
            if stage in self.load_sharing:
                raise CaseError(
                    f"rating: give load_sharing or planet_position_errors for {stage!r}, "
                    "not both (the errors make the model compute K_gamma)"
                )
            for k, value in enumerate(errors):
                if not (isinstance(value, (int, float)) and math.isfinite(value)
                        and abs(value) < 1e-3):
                    raise CaseError(
                        f"rating.planet_position_errors[{stage!r}][{k}] must be a finite "
                        f"error in m below 1 mm (got {value!r}; 50 um is 50e-6)"
                    )
        if not (isinstance(self.accuracy_grade, int) and 1 <= self.accuracy_grade <= 12):
            raise CaseError(
                f"rating.accuracy_grade must be an ISO 1328-1 grade 1..12 "
                f"(got {self.accuracy_grade!r})"
            )
        if not isinstance(self.face_load_from_model, bool):
            raise CaseError("rating.face_load_from_model must be True or False "
                            f"(got {self.face_load_from_model!r})")
        if self.duty_cycle is not None and not isinstance(self.duty_cycle, DutyCycle):
            raise CaseError("rating.duty_cycle must be a DutyCycle or None")
        names = [b.name for b in self.bearings]
        if len(set(names)) != len(names):
            raise CaseError(f"rating.bearings: names must be unique (got {names})")


def load_rating(reference: str | os.PathLike) -> tuple[object, Rating]:
    """The ``case`` and the ``rating`` a case file defines.

    Raises
    ------
    CaseError
        When the case file defines no ``rating = Rating(...)``: one line saying what
        to add.
    """
    from .case import Case
    from .case_files import load_case_module

    directory, module = load_case_module(reference)
    case = getattr(module, "case", None)
    if not isinstance(case, Case):
        raise CaseError(f"{directory / 'case.py'} must define a module-level `case = Case(...)`")
    rating = getattr(module, "rating", None)
    if not isinstance(rating, Rating):
        raise CaseError(
            f"{directory / 'case.py'} has no rating data: add a module-level "
            "`rating = Rating(materials={...}, rated_torque=..., rated_speed_rpm=..., "
            "application_factor=..., required_sh=..., required_sf=...)` "
            "(from pygear.model.rating import Rating, Material)"
        )
    return case, rating
