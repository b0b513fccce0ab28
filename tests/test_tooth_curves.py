"""A damaged tooth follows its own pair curve in the tooth-contact table.

The reference is the potential-energy module's own mesh stiffness (fortran
tooth_potential_energy, by its summation of the pair curves, not the table's):
``MeshStiffness.mesh`` over a healthy cycle and ``faulty_mesh`` while the damaged tooth
passes, its pair entering at s = 0.  The table holds the healthy curve as its tabulated
law and the damaged tooth's curve (``faulty_curve``) for that one tooth.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pygear.assembly.contact_table import LAW_CODES, ContactTable, with_tooth_curves
from pygear.assembly.tooth_stiffness import ChippedTooth, RootCrack, ToothBody, mesh_stiffness
from pygear.model import GearGeometry, MeshGeometry

MODULE, WIDTH = 3.2e-3, 0.016  # m: Tian's (2004) pair, as in test_potential_energy
TEETH = (19, 48)
BODIES = (ToothBody(2.068e11, 0.3, 0.010), ToothBody(2.068e11, 0.3, 0.030))
N_CYCLE = 100


def healthy_table(curve: np.ndarray, mean: float, eps: float) -> ContactTable:
    """One mesh, Z1 = 19, Z2 = 48, tooth 0 of both gears in the pair entering at s = 0."""
    return ContactTable(
        names=("mesh",),
        gears=(("pinion", "wheel"),),
        angles=(("pinion", "ground"),),
        teeth=np.array([[TEETH[0]], [TEETH[1]]], dtype=np.int32, order="F"),
        cycle_sign=np.ones(1, dtype=np.int32),
        tooth_offset=np.zeros((2, 1), dtype=np.int32, order="F"),
        mean_stiffness=np.array([mean]),
        contact_ratio=np.array([eps]),
        end_to_peak=np.array([1.0]),
        phase=np.zeros(1),
        law=np.array([LAW_CODES["tabulated"]], dtype=np.int32),
        curve_start=np.zeros(1, dtype=np.int32),
        curve_size=np.array([curve.size], dtype=np.int32),
        curve=curve,
        factor_start=np.full((2, 1), -1, dtype=np.int32, order="F"),
        factor=np.ones(1),
        max_pairs=int(math.ceil(eps)) + 1,
    )


@pytest.mark.parametrize(
    "fault", [RootCrack(1, 2e-3, 45.0), RootCrack(2, 2e-3, 45.0), ChippedTooth(1, 0.3)]
)
def test_damaged_tooth_changes_the_table_only_while_in_mesh(fault):
    """Over two turns of gear 1: the stiffness equals the healthy table wherever the
    damaged tooth is out of mesh, and the potential-energy module's faulty mesh stiffness
    while its pair is in mesh (s in [0, eps) and again one turn of its gear later).

    Tolerances: the table interpolates 2001 samples of each curve linearly (1e-6 of the
    stiffness, as in test_potential_energy); elsewhere both tables run the same
    arithmetic on the same healthy pairs (1e-12 allows any rounding order)."""
    pair = MeshGeometry(
        GearGeometry(TEETH[0], MODULE, WIDTH), GearGeometry(TEETH[1], MODULE, WIDTH)
    )
    result = mesh_stiffness(pair, BODIES, fault=fault, n_sample=2001, n_cycle=N_CYCLE)
    curve, mean, eps = result.tabulated_curve()
    healthy = healthy_table(curve, mean, eps)
    damaged = with_tooth_curves(healthy, {(0, fault.gear, 0): result.faulty_curve()})
    turn = TEETH[fault.gear - 1]  # the damaged tooth is back after Z of its gear's cycles
    cycle = np.arange(-2 * N_CYCLE, (turn + 3) * N_CYCLE) / N_CYCLE
    theta = 2 * np.pi * cycle[:, None] / TEETH[0]
    with_damage = damaged.series(theta)["stiffness"][:, 0]
    without = healthy.series(theta)["stiffness"][:, 0]

    in_mesh = ((cycle >= 0) & (cycle < eps)) | ((cycle >= turn) & (cycle < turn + eps))
    np.testing.assert_allclose(with_damage[~in_mesh], without[~in_mesh], rtol=1e-12)
    assert np.max(np.abs(with_damage[in_mesh] / without[in_mesh] - 1)) > 1e-3  # it shows

    window = result.window_position  # [0, ceil(eps)), the damaged pair entering at 0
    for start in (0, turn):
        index = np.round((start + window) * N_CYCLE).astype(int) + 2 * N_CYCLE
        np.testing.assert_allclose(with_damage[index], result.faulty_mesh, rtol=1e-6)
    outside = (cycle >= 2) & (cycle < 3)  # a healthy cycle, against the module's own
    np.testing.assert_allclose(
        with_damage[outside], np.interp(cycle[outside] % 1, result.cycle_position, result.mesh),
        rtol=1e-6,
    )  # fmt: skip


def test_tooth_curve_keys_are_checked():
    """A curve for a tooth or gear the mesh does not have is refused before the kernel."""
    pair = MeshGeometry(
        GearGeometry(TEETH[0], MODULE, WIDTH), GearGeometry(TEETH[1], MODULE, WIDTH)
    )
    result = mesh_stiffness(pair, BODIES, n_sample=11)
    table = healthy_table(*result.tabulated_curve())
    with pytest.raises(ValueError, match="tooth not in 0 .. 18"):
        with_tooth_curves(table, {(0, 1, 19): result.faulty_curve()})
    with pytest.raises(ValueError, match="no such mesh and gear"):
        with_tooth_curves(table, {(0, 3, 0): result.faulty_curve()})
