"""The loaded contact of a mesh tabulated over mesh position and load (law ``loaded_contact``).

For one mesh, :func:`loaded_contact_table` runs the loaded tooth contact analysis
(:func:`pygear.assembly.ltca.loaded_contact`) once, at the operating load F_0 and at
:data:`LOAD_FACTORS` times it, over one mesh cycle: the loaded and unloaded transmission
error delta(F, s), delta_0(s), each pair's force F_k(F, s) and the secant mesh stiffness
k(F, s) = F / (delta - delta_0).  Between the tabulated loads the stiffness is
interpolated linearly in the load, so it stays between its neighbours.

The dynamics take the table at F_0 as a displacement excitation with a load-dependent
stiffness: the mesh force along the drive flank's compression c is

    F = k(F_0, s) (c - delta_0(s)),

the secant stiffness at the operating load as the mesh's ``tabulated`` law (each pair's
share F_k / (delta - delta_0) along its own path p = s + k, :meth:`~LoadedContactTable.
secant_pair_curve`) and the unloaded TE delta_0 as the contact table's excitation
(:meth:`~LoadedContactTable.excitation`).  Under F_0 the static compression is
c = delta_0 + F_0 / k(F_0, s) = delta(F_0, s), the LTCA's loaded TE itself, exactly and at
every position (the secant stiffness is defined so); the choice keeps the mesh's mean
stiffness the LTCA's and its excitation the load-free geometry (modifications and the
mesh-periodic deviations), so a change of the mean load moves the deflection through k
alone.  For perfect flanks delta_0 = 0 and k is the potential-energy law's curve.

Per-tooth deviations (single pitch deviations, runout) repeat once per revolution:
:func:`tooth_pair_curves` tabulates the loaded contact over a whole revolution and gives
every tooth its own pair curve of the *TE-equivalent* stiffness
k_e(s) = F_0 / (delta(s) - c), c the one constant that keeps the LTCA's mean mesh stiffness
(a spring k_e deflects under F_0 by the loaded TE less c; to first order in the TE
variation it is the displacement excitation above).  A mesh with such deviations runs
that stiffness over the revolution and no excitation.
"""

from __future__ import annotations

import dataclasses
import functools
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError
from ..model.gear_geometry import MeshGeometry
from ..model.micro_geometry import Deviations, Modifications
from .ltca import loaded_contact
from .tooth_stiffness import ToothBody

__all__ = [
    "LOAD_FACTORS",
    "LoadedContactTable",
    "check_spread",
    "loaded_contact_table",
    "mesh_periodic",
    "operating_force",
    "revolution_pair_curves",
    "tooth_pair_curves",
]

LOAD_FACTORS = (0.25, 0.5, 1.0, 1.5, 2.0)
"""Loads of the table over the operating load (1.0: the operating load itself)."""

N_SLICE = 20
"""Slices along the face of the table's LTCA (spur: any count gives the same pair)."""

N_POSITION = 40
"""Positions per mesh cycle of the table's LTCA."""

SAMPLES = 201
"""Samples of a pair curve over the path (the potential-energy law's count)."""

MAX_STIFFNESS_SPREAD = 4.0
"""Largest over smallest TE-equivalent stiffness over a cycle (or a revolution) that
passes without a warning: about twice a spur pair's double- over single-contact
stiffness.  Beyond it the loaded TE varies by about the static deflection itself (a
light load, a large deviation), where the first-order equivalence with a displacement
excitation no longer holds and the explicit time loop may need smaller steps."""


def check_spread(stiffness: np.ndarray, force: float, path: str) -> None:
    """Warn when the TE-equivalent stiffness spreads beyond :data:`MAX_STIFFNESS_SPREAD`."""
    spread = float(stiffness.max() / stiffness.min())
    if spread > MAX_STIFFNESS_SPREAD:
        warnings.warn(
            f"{path}: the loaded_contact law's TE-equivalent stiffness spreads by "
            f"{spread:.3g} over the cycle at the operating load {force:.6g} N: the loaded "
            "TE varies by about the static deflection (raise the mesh's line_load to the "
            "load it runs at, or check the micro-geometry's amounts)",
            stacklevel=3,
        )


@dataclass(frozen=True, eq=False)
class LoadedContactTable:
    """A mesh's loaded contact over one mesh cycle and a few loads.

    Attributes
    ----------
    force : ndarray, shape (n_load,)
        Loads along the transverse line of action [N], increasing.
    operating_force : float
        F_0, the load the dynamics run at [N] (one of ``force``).
    position : ndarray, shape (n_position,)
        Mesh positions s over one cycle [mesh cycles].
    te_unloaded : ndarray, shape (n_position,)
        delta_0(s) [m].
    te_loaded : ndarray, shape (n_load, n_position)
        delta(F, s) [m].
    pair_force : ndarray, shape (n_load, n_position, n_pair)
        F_k(F, s) of pair k [N].
    contact_ratio : float
        eps_alpha + eps_beta of the pair's path [-].
    """

    force: np.ndarray
    operating_force: float
    position: np.ndarray
    te_unloaded: np.ndarray
    te_loaded: np.ndarray
    pair_force: np.ndarray
    contact_ratio: float

    def secant_stiffness(self, force: float) -> np.ndarray:
        """k(F, s) = F / (delta - delta_0) [N/m] at a load inside the table, linear in
        the load between the tabulated loads."""
        table = self.force[:, None] / (self.te_loaded - self.te_unloaded[None, :])
        if not self.force[0] <= force <= self.force[-1]:
            raise CaseError(
                f"force {force!r} N lies outside the loaded-contact table "
                f"[{self.force[0]:.6g}, {self.force[-1]:.6g}] N"
            )
        return np.array([np.interp(force, self.force, column) for column in table.T])

    def mean_stiffness(self, force: float) -> float:
        """The cycle's mean of :meth:`secant_stiffness` [N/m]."""
        return float(self.secant_stiffness(force).mean())

    def _operating(self) -> tuple[np.ndarray, np.ndarray]:
        index = int(np.argmin(np.abs(self.force - self.operating_force)))
        return self.te_loaded[index], self.pair_force[index]

    def te_offset(self) -> float:
        """c of the TE-equivalent stiffness at the operating load [m]."""
        loaded, _ = self._operating()
        return equivalent_offset(self.operating_force, loaded,
                                 self.mean_stiffness(self.operating_force))  # fmt: skip

    def equivalent_stiffness(self) -> np.ndarray:
        """k_e(s) = F_0 / (delta(s) - c) at the operating load [N/m]."""
        loaded, _ = self._operating()
        return self.operating_force / (loaded - self.te_offset())

    def secant_pair_curve(self, samples: int = SAMPLES) -> np.ndarray:
        """One pair's share of the secant stiffness, F_k / (delta - delta_0) [N/m] at the
        operating load, at ``samples`` equal steps over its path [0, eps]."""
        loaded, pair_force = self._operating()
        shares = pair_force / (loaded - self.te_unloaded)[:, None]
        return _along_path(self.position, shares, self.contact_ratio, samples)

    def excitation(self, samples: int = SAMPLES) -> np.ndarray:
        """The unloaded TE delta_0(s) [m] at ``samples`` equal steps over one mesh cycle
        s = 0 .. 1 (periodic: the last sample is the first)."""
        grid = np.linspace(0.0, 1.0, samples)
        values = np.interp(grid, self.position, self.te_unloaded, period=1.0)
        values[-1] = values[0]
        return values

    def pair_curve(self, samples: int = SAMPLES) -> np.ndarray:
        """One pair's TE-equivalent stiffness F_k / (delta - c) [N/m] at ``samples``
        equal steps over its path [0, eps]."""
        loaded, pair_force = self._operating()
        shares = pair_force / (loaded - self.te_offset())[:, None]
        return _along_path(self.position, shares, self.contact_ratio, samples)


def equivalent_offset(force: float, loaded: np.ndarray, mean: float) -> float:
    """The c with mean(F / (delta - c)) = ``mean`` (c below every delta) [m]."""
    from scipy.optimize import brentq  # only a loaded_contact law needs SciPy

    low_bound = float(loaded.min())

    def excess(c: float) -> float:
        return float(np.mean(force / (loaded - c))) - mean

    if excess(0.0) == 0.0:
        return 0.0
    span = float(np.ptp(loaded)) + force / mean
    lower = low_bound - span
    while excess(lower) > 0:
        lower -= span
    upper = low_bound - 1e-9 * span
    return float(brentq(excess, lower, upper, xtol=1e-16, rtol=1e-14))


def _along_path(position: np.ndarray, shares: np.ndarray, eps: float, samples: int) -> np.ndarray:
    """Pair values at (s, k) gathered along the path p = s + k, resampled over [0, eps]."""
    p = (position[:, None] + np.arange(shares.shape[1])[None, :]).ravel()
    inside = p <= eps * (1 + 1e-12)
    order = np.argsort(p[inside])
    p, k = p[inside][order], shares.ravel()[inside][order]
    if p[-1] < eps and p.size > 1:  # the last step to the end: extrapolated linearly
        end = k[-1] + (k[-1] - k[-2]) * (eps - p[-1]) / (p[-1] - p[-2])
        p, k = np.append(p, eps), np.append(k, max(end, 0.0))
    return np.interp(np.linspace(0.0, eps, samples), p, k)


def mesh_periodic(mods: Modifications | None) -> Modifications | None:
    """The modifications without the deviations that differ tooth by tooth (single pitch
    deviations, runout): what repeats every mesh cycle."""
    if mods is None or mods.deviations is None:
        return mods
    deviations = dataclasses.replace(mods.deviations, pitch=(), runout=0.0)
    if deviations == Deviations():
        deviations = None
    return dataclasses.replace(mods, deviations=deviations)


def operating_force(geometry: MeshGeometry, line_load: float) -> float:
    """F_0 = w b along the transverse line of action [N] from a line load w [N/mm] on the
    common face width b."""
    width = min(geometry.gear1.face_width, geometry.gear2.face_width)
    return float(line_load) * 1e3 * width


def loaded_contact_table(
    geometry: MeshGeometry,
    bodies: tuple[ToothBody, ToothBody],
    modifications: tuple[Modifications | None, Modifications | None],
    force: float,
    *,
    driving_gear: int,
    path: str,
) -> LoadedContactTable:
    """Tabulate a mesh's loaded contact over one mesh cycle at :data:`LOAD_FACTORS` times
    ``force`` (see the module docstring); per-tooth deviations are left out."""
    forces = np.array(LOAD_FACTORS) * force
    mods = tuple(mesh_periodic(m) for m in modifications)
    ds = loaded_contact(geometry, bodies, forces, modifications=mods, n_slice=N_SLICE,
                        n_position=N_POSITION, driving_gear=driving_gear, path=path)  # fmt: skip
    return _table(ds, forces, force)


def _table(ds, forces: np.ndarray, force: float) -> LoadedContactTable:
    width = float(ds.attrs["face_width"])
    pair_force = ds.line_load.values.sum(axis=3) * width / ds.face.size
    return LoadedContactTable(
        force=forces,
        operating_force=float(force),
        position=ds.position.values,
        te_unloaded=ds.te_unloaded.values,
        te_loaded=ds.te_loaded.values,
        pair_force=pair_force,
        contact_ratio=float(ds.attrs["eps_alpha"] + ds.attrs["eps_beta"]),
    )


def tooth_pair_curves(*args, **kwargs) -> np.ndarray:
    """:func:`revolution_pair_curves`, cached by its frozen arguments (a sweep or a
    batch of scenes tabulates each revolution once); the result is read-only."""
    return _cached_curves(*args, **kwargs)


def revolution_pair_curves(
    geometry: MeshGeometry,
    bodies: tuple[ToothBody, ToothBody],
    modifications: tuple[Modifications | None, Modifications | None],
    force: float,
    gear: int,
    *,
    driving_gear: int,
    path: str,
    samples: int = SAMPLES,
) -> np.ndarray:
    """Each tooth's own pair curve over a revolution of gear ``gear`` (1 or 2, geometry
    order) whose single pitch deviations or runout repeat once per revolution.

    The LTCA runs over Z mesh cycles (Z the gear's teeth) at ``force``, with the other
    gear's per-tooth deviations left out; pair k at position s holds tooth
    floor(s) - k of the gear, at p = s - floor(s) + k of its path.  Each pair carries
    F_k(s) / (delta(s) - c), c the TE-equivalent offset of the revolution (its mean
    stiffness the revolution's mean secant stiffness), so the teeth' curves sum to the
    TE-equivalent stiffness of the whole revolution.

    Returns
    -------
    ndarray, shape (Z, samples)
        Tooth j's pair stiffness [N/m] at ``samples`` equal steps over [0, eps].
    """
    teeth = geometry.gear1.teeth if gear == 1 else geometry.gear2.teeth
    mods = list(modifications)
    other = 1 - (gear - 1)
    mods[other] = mesh_periodic(mods[other])
    ds = loaded_contact(geometry, bodies, [force], modifications=tuple(mods), n_slice=N_SLICE,
                        n_position=N_POSITION, cycles=teeth, driving_gear=driving_gear,
                        path=path)  # fmt: skip
    table = _table(ds, np.array([force]), force)
    loaded, pair_force = table.te_loaded[0], table.pair_force[0]
    mean = table.mean_stiffness(force)
    offset = equivalent_offset(force, loaded, mean)
    check_spread(force / (loaded - offset), force, path)
    shares = pair_force / (loaded - offset)[:, None]
    cycle = np.floor(table.position + 1e-9).astype(int)
    fraction = table.position - cycle
    curves = np.empty((teeth, samples))
    pairs = shares.shape[1]
    for tooth in range(teeth):
        # pair k holds this tooth during the cycle tooth + k (modulo the revolution)
        rows = [np.flatnonzero(cycle == (tooth + k) % teeth) for k in range(pairs)]
        p = np.concatenate([fraction[r] + k for k, r in enumerate(rows)])
        k_values = np.concatenate([shares[r, k] for k, r in enumerate(rows)])
        curves[tooth] = _along_path(p, k_values[:, None], table.contact_ratio, samples)
    return curves


@functools.lru_cache(maxsize=32)
def _cached_curves(*args, **kwargs) -> np.ndarray:
    curves = revolution_pair_curves(*args, **kwargs)
    curves.setflags(write=False)
    return curves
