"""A case's design load cases: hub wind speeds x seeds x duration, each a transient run
of one of the case's scenes driven by a rotor torque series (:class:`DesignLoadCases`).

A case file defines them beside its ``case`` as a module-level
``design_load_cases = DesignLoadCases(...)``; ``pygear batch CASE --dlc`` runs them
(:mod:`pygear.runs.dlc`), one streamed file per load case, and combines their
reductions into a load spectrum per year, each load case weighted by the hours a year
its wind speed blows (a Weibull distribution, IEC 61400-1 ed.3 section 6.3.1.1 with
the shape 2 of a Rayleigh distribution by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import CaseError
from .reduction_settings import Reductions
from .transient_settings import Probe

__all__ = [
    "DLC_SOURCES",
    "HOURS_PER_YEAR",
    "DesignLoadCases",
    "LoadCase",
    "load_design_load_cases",
]

DLC_SOURCES = ("kaimal", "openfast")
"""Where a load case's rotor torque comes from: a synthetic Kaimal wind through the
rotor's Cp curve (:mod:`pygear.analysis.time.wind`), or OpenFAST output files
(:func:`pygear.io_openfast.read_openfast_output`)."""

HOURS_PER_YEAR = 8766.0
"""Hours of a mean (Julian) year, 365.25 x 24."""


@dataclass(frozen=True)
class LoadCase:
    """One load case of a table: its name (file stem), wind speed, seed, the hours a
    year it stands for and, for OpenFAST input, its file."""

    name: str
    wind_speed: float
    seed: int
    hours_per_year: float
    openfast_file: str | None = None


@dataclass(frozen=True)
class DesignLoadCases:
    """A design load case table (wind speed x seed, one duration).

    Parameters
    ----------
    scene : str
        The case's transient scene each load case runs (its time step, probes,
        input and output members and reductions); the load case replaces its drive,
        load, duration, starting speed and mean window.
    wind_speeds : tuple of float
        Hub wind speeds [m/s], > 0, increasing.
    seeds : tuple of int
        Turbulence seeds, >= 0, distinct; every wind speed runs each.
    duration : float
        Simulated time of each load case [s] (IEC 61400-1: 600 s).
    source : {"kaimal", "openfast"}
        The rotor torque and speed: synthetic (Kaimal wind, the rotor's Cp curve) or
        read from ``openfast_files``.
    openfast_files : tuple of str
        With ``source="openfast"``: one OpenFAST output file per load case, wind
        speed major and seed minor (relative paths from the case directory).
    turbulence_class : {"A", "B", "C"}
        IEC 61400-1 turbulence category (I_ref 0.16, 0.14, 0.12).
    input_rate : float
        Sample rate of the synthetic torque series [Hz]; the drive interpolates it.
    regulation_time_constant : float
        Time constant of the slow wind the rotor speed and pitch follow [s].
    weibull_shape, weibull_mean : float
        k [-] and the mean [m/s] of the hub wind speed's Weibull distribution.
    wind_bin_edges : tuple of float, optional
        Edges of the wind speed bins [m/s] (one more than the wind speeds, each speed
        inside its bin); default half way between the speeds, the outer bins as wide
        as their neighbours' half spacing (a single speed: +-1 m/s).
    reductions : Reductions, optional
        What each load case reduces (default: the scene's); the load spectrum needs
        its rainflow matrices and load duration distributions.
    probes : tuple of Probe
        Replace the scene's probes (default: the scene's).
    """

    scene: str
    wind_speeds: tuple[float, ...]
    seeds: tuple[int, ...]
    duration: float = 600.0
    source: str = "kaimal"
    openfast_files: tuple[str, ...] = ()
    turbulence_class: str = "B"
    input_rate: float = 20.0
    regulation_time_constant: float = 5.0
    weibull_shape: float = 2.0
    weibull_mean: float = 10.0
    wind_bin_edges: tuple[float, ...] | None = None
    reductions: Reductions | None = None
    probes: tuple[Probe, ...] = field(default=())

    def __post_init__(self) -> None:
        for name in ("wind_speeds", "seeds", "openfast_files", "probes"):
            value = getattr(self, name)
            if not isinstance(value, tuple):
                object.__setattr__(self, name, tuple(value) if value is not None else ())

    def validate(self, path: str = "design_load_cases") -> None:
        """Raise :class:`CaseError` naming the first bad setting."""
        speeds = self.wind_speeds
        if not speeds or not all(_positive(v) for v in speeds):
            raise CaseError(f"{path}.wind_speeds must be one or more speeds > 0 m/s")
        if any(b <= a for a, b in zip(speeds, speeds[1:])):
            raise CaseError(f"{path}.wind_speeds must increase strictly (got {speeds})")
        if not self.seeds or not all(
            isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in self.seeds
        ):
            raise CaseError(f"{path}.seeds must be one or more whole numbers >= 0")
        if len(set(self.seeds)) != len(self.seeds):
            raise CaseError(f"{path}.seeds must be distinct (got {self.seeds})")
        for name in (
            "duration",
            "input_rate",
            "regulation_time_constant",
            "weibull_shape",
            "weibull_mean",
        ):
            if not _positive(getattr(self, name)):
                raise CaseError(f"{path}.{name} must be > 0 (got {getattr(self, name)!r})")
        if self.duration * self.input_rate < 4:
            raise CaseError(
                f"{path}: duration x input_rate must give at least 4 samples of the torque "
                f"series (got {self.duration:g} s x {self.input_rate:g} Hz)"
            )
        if self.source not in DLC_SOURCES:
            raise CaseError(
                f"{path}.source must be one of {', '.join(DLC_SOURCES)} (got {self.source!r})"
            )
        cases = len(speeds) * len(self.seeds)
        if self.source == "openfast" and len(self.openfast_files) != cases:
            raise CaseError(
                f"{path}.openfast_files must name one file per load case, wind speed major: "
                f"{cases} (got {len(self.openfast_files)})"
            )
        if self.source == "kaimal" and self.openfast_files:
            raise CaseError(f"{path}.openfast_files needs source='openfast'")
        if self.turbulence_class not in ("A", "B", "C"):
            raise CaseError(
                f"{path}.turbulence_class must be A, B or C (got {self.turbulence_class!r})"
            )
        edges = self.bin_edges()
        if len(edges) != len(speeds) + 1 or any(
            not (lo < v < hi) for lo, v, hi in zip(edges, speeds, edges[1:])
        ):
            raise CaseError(
                f"{path}.wind_bin_edges must be {len(speeds) + 1} increasing edges, each "
                f"wind speed inside its bin (got {edges})"
            )
        if edges[0] < 0:
            raise CaseError(f"{path}.wind_bin_edges must be >= 0 m/s (got {edges[0]!r})")

    def bin_edges(self) -> tuple[float, ...]:
        """Edges of the wind speed bins [m/s]."""
        if self.wind_bin_edges is not None:
            return tuple(float(e) for e in self.wind_bin_edges)
        v = [float(s) for s in self.wind_speeds]
        if len(v) == 1:
            return (max(v[0] - 1.0, 0.0), v[0] + 1.0)
        middles = [(a + b) / 2.0 for a, b in zip(v, v[1:])]
        first = max(v[0] - (v[1] - v[0]) / 2.0, 0.0)
        return (first, *middles, v[-1] + (v[-1] - v[-2]) / 2.0)

    def weibull_cdf(self, wind_speed: float) -> float:
        """P(V < wind_speed) of the Weibull distribution with the given shape and mean."""
        k = self.weibull_shape
        scale = self.weibull_mean / math.gamma(1.0 + 1.0 / k)
        return 1.0 - math.exp(-((max(wind_speed, 0.0) / scale) ** k))

    def load_cases(self) -> list[LoadCase]:
        """Every load case, wind speed major, with the hours a year it stands for:
        8766 h x P(wind in its bin) / number of seeds."""
        edges = self.bin_edges()
        cases = []
        for i, speed in enumerate(self.wind_speeds):
            share = self.weibull_cdf(edges[i + 1]) - self.weibull_cdf(edges[i])
            for j, seed in enumerate(self.seeds):
                file = (
                    self.openfast_files[i * len(self.seeds) + j]
                    if self.source == "openfast"
                    else None
                )
                cases.append(
                    LoadCase(
                        name=load_case_name(speed, seed),
                        wind_speed=float(speed),
                        seed=int(seed),
                        hours_per_year=HOURS_PER_YEAR * share / len(self.seeds),
                        openfast_file=file,
                    )
                )
        return cases


def load_case_name(wind_speed: float, seed: int) -> str:
    """File stem of a load case: ``dlc_12p5ms_seed3`` for 12.5 m/s and seed 3."""
    return f"dlc_{float(wind_speed):g}ms_seed{seed}".replace(".", "p")


def _positive(value: object) -> bool:
    return (
        isinstance(value, (int, float))
        and not isinstance(value, bool)
        and math.isfinite(value)
        and value > 0
    )


def load_design_load_cases(reference) -> tuple:
    """The case and the ``design_load_cases`` its case file defines, and its directory.

    Returns
    -------
    tuple
        (case, design load cases, case directory).

    Raises
    ------
    CaseError
        When the case file defines no ``design_load_cases = DesignLoadCases(...)``, or
        the table or its scene breaks a rule.
    """
    from .case import Case
    from .case_files import load_case_module

    directory, module = load_case_module(reference)
    case = getattr(module, "case", None)
    if not isinstance(case, Case):
        raise CaseError(f"{directory / 'case.py'} must define a module-level `case = Case(...)`")
    table = getattr(module, "design_load_cases", None)
    if not isinstance(table, DesignLoadCases):
        raise CaseError(
            f"{directory / 'case.py'} has no design load cases: add a module-level "
            "`design_load_cases = DesignLoadCases(scene=..., wind_speeds=..., seeds=...)` "
            "(from pygear.model.dlc_settings import DesignLoadCases)"
        )
    table.validate()
    names = [scene.name for scene in case.scenes]
    if table.scene not in names:
        raise CaseError(
            f"design_load_cases.scene {table.scene!r} is not a scene of the case "
            f"(scenes: {', '.join(names)})"
        )
    scene = case.scene(table.scene)
    if scene.transient is None or "transient" not in scene.analyses:
        raise CaseError(
            f"design_load_cases.scene {table.scene!r} must be a transient scene "
            "(analyses=('transient',) with transient=Transient(...))"
        )
    if table.source == "openfast":
        for file in table.openfast_files:
            if not (Path(directory) / file).is_file():
                raise CaseError(f"design_load_cases.openfast_files: {file!r} does not exist")
    return case, table, Path(directory)
