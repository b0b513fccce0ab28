r"""The meshes' displacement excitation as a periodic force of the harmonic balance.

A mesh whose contact table carries a displacement excitation e_m(s) (the unloaded
transmission error of the ``loaded_contact`` law, along the drive flank's compression;
:mod:`pygear.assembly.loaded_contact_table`) has the mesh force
k_m(tau) (delta_m - s_m e_m(tau)) along its deflection delta_m = b_m . q, as in the
transient kernel.  Moved to the right-hand side of the equation of motion the
excitation is a force on the DOFs,

    F_e(tau) = sum_m k_m(tau) s_m e_m(tau) b_m,    f_e(tau) = B^T (k s e)(tau)

in the elastic modal coordinates (B = [b_m^T Psi], :mod:`.system`), periodic in the
fundamental's phase tau.  Its mean adds to the static load f and its harmonics
f_k = (1/N) sum_tau f_e(tau) e^{-2 pi i k tau} are the ``harmonic_force`` of
:class:`~.system.ResponseSystem` (f + sum_k (f_k e^{i k omega t} + c.c.)).  The mesh
force the balance reports is then s_m k_m (delta_m - s_m e_m) (:func:`.hill.mesh_signals`).

The quasi-periodic balance of meshes at unrelated fundamentals (:mod:`.quasi`) takes no
periodic force: :func:`.system.response_system` builds such a system's table with the
``loaded_contact`` meshes on their first-order TE-equivalent stiffness instead
(``build_contact_table(..., excitation=False)``), and :func:`mesh_excitation` refuses an
excitation there.  The contact-loss balance (:mod:`.nonlinear`) tests contact at
s_m delta_m > 0 and reports k g(s_m delta_m), not the compression less the excitation:
:func:`refuse_excitation` keeps it from a system with one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...assembly.contact_table import ContactTable
from ...errors import CaseError

__all__ = ["MeshExcitation", "mesh_excitation", "refuse_excitation"]

@dataclass(frozen=True)
class MeshExcitation:
    """The displacement excitation of a system's meshes over one fundamental period.

    Attributes
    ----------
    excitation : ndarray, shape (samples, n_mesh)
        s_m e_m(tau) along the mesh deflections [m].
    mean_force : ndarray, shape (n,)
        Mean of f_e over the period in modal coordinates.
    harmonic_force : ndarray, complex, shape (K, n)
        f_k, k = 1..K, of f_e in modal coordinates, K = samples / 2 - 1.
    """

    excitation: np.ndarray
    mean_force: np.ndarray
    harmonic_force: np.ndarray


def mesh_excitation(
    table: ContactTable,
    theta: np.ndarray,
    stiffness: np.ndarray,
    contact_sign: np.ndarray,
    mesh_rows: np.ndarray,
    *,
    groups: int = 1,
) -> MeshExcitation | None:
    """The excitation force of the meshes that carry a displacement excitation.

    Parameters
    ----------
    table : ContactTable
        The meshes' contact table.
    theta : ndarray, shape (samples, n_mesh)
        Gear 1 rotations relative to the carrier over one fundamental period [rad].
    stiffness : ndarray, shape (samples, n_mesh)
        k_m(tau) at those states [N/m].
    contact_sign : ndarray, shape (n_mesh,)
        s_m of the loaded flanks.
    mesh_rows : ndarray, shape (n_mesh, n)
        B, the mesh deflection per modal coordinate [m].
    groups : int
        Frequency groups of the system; an excitation needs a single one.

    Returns
    -------
    MeshExcitation or None
        None when no mesh carries an excitation.

    Raises
    ------
    CaseError
        The meshes run at several unrelated fundamentals (the quasi-periodic balance
        takes no excitation force).
    """
    if table.excitation is None:
        return None
    if groups > 1:
        excited = [name for name, size in zip(table.names, table.excitation_size) if size]
        raise CaseError(
            f"meshes {', '.join(excited)}: a displacement excitation (law loaded_contact) "
            "needs the meshes on one fundamental in the harmonic balance; this gearbox "
            "has several frequency groups (use the transient)"
        )
    excitation = np.asarray(contact_sign)[None, :] * table.excitation_at(theta)
    force = (np.asarray(stiffness) * excitation) @ mesh_rows  # (samples, n)
    samples = force.shape[0]
    spectrum = np.fft.rfft(force, axis=0) / samples
    count = samples // 2 - 1  # every harmonic below Nyquist: the balance takes its own H
    return MeshExcitation(
        excitation=excitation,
        mean_force=force.mean(axis=0),
        harmonic_force=np.ascontiguousarray(spectrum[1 : count + 1]),
    )


def refuse_excitation(system, analysis: str) -> None:
    """Raise :class:`CaseError` naming the meshes when ``system`` (a
    :class:`~.system.ResponseSystem`) carries a displacement excitation, which
    ``analysis`` does not take."""
    if getattr(system, "excitation", None) is None:
        return
    excited = [name for name, e in zip(system.names, system.excitation.T) if np.any(e)]
    if not excited:
        return
    raise CaseError(
        f"meshes {', '.join(excited)}: {analysis} does not take the displacement excitation "
        "of law loaded_contact yet (run the linear response, or the transient with the "
        "tooth_separation effect)"
    )
