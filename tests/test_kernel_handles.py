"""The kernel keeps tooth-contact tables and transient problems under handles: several
live at once, each answers for itself, and a freed handle is refused.

References are closed forms derived here: the mean-preserving parabola of a single
tooth pair, k = 3 kbar / (eps (2 + lambda)) [1 - (1 - lambda)(2 p / eps - 1)^2]
(docs/model.md §5.2), and the displacement of an undamped oscillator under the
average-acceleration Newmark rule started on its equation of motion,
x_n = x0 cos(n w~ dt) with tan(w~ dt / 2) = w dt / 2 (Hughes, *The Finite Element
Method*, 9.3: the rule keeps the amplitude and shortens the frequency).
"""

from __future__ import annotations

import dataclasses
import gc
import math
import pickle

import numpy as np
import pytest
from conftest import single_mesh_table

from pygear.assembly.contact_table import ContactTable
from pygear.kernel import _kernel
from pygear.kernel.calls import KernelError
from pygear.kernel.newmark import BandedNewmark, KernelProbe

HANDLE_NOT_LIVE = 5  # contact_table: ct_err_handle
PROBLEM_NOT_LIVE = 10  # newmark_support: nm_err_handle


def parabola_table(mean_stiffness: float, contact_ratio: float, end_to_peak: float) -> ContactTable:
    """One parabola-law mesh with Z1 = Z2 = 1, so the mesh cycle is s = theta / 2 pi."""
    return single_mesh_table(
        mean_stiffness, contact_ratio, "parabola", end_to_peak, angles=("pinion", "carrier")
    )


def parabola_mesh(s: float, mean_stiffness: float, eps: float, lam: float) -> float:
    """Sum of the pair stiffnesses at mesh cycle s (pairs at frac(s) + k below eps)."""
    peak = 3 * mean_stiffness / (eps * (2 + lam))
    positions = [p for p in (s % 1 + k for k in range(3)) if p < eps]
    return sum(peak * (1 - (1 - lam) * (2 * p / eps - 1) ** 2) for p in positions)


def test_two_tables_evaluated_alternately_answer_for_themselves():
    soft = (2.0e8, 1.6, 0.5)
    stiff = (9.0e8, 1.3, 0.8)
    tables = [parabola_table(*soft), parabola_table(*stiff)]
    for s in np.linspace(0.0, 3.0, 13):
        for table, (mean, eps, lam) in zip(tables, (soft, stiff)):
            stiffness = table.evaluate(np.array([2 * math.pi * s]))["stiffness"][0]
            # the kernel divides theta by 2 pi and adds products: a few ulp
            assert stiffness == pytest.approx(parabola_mesh(s, mean, eps, lam), rel=1e-12)
    assert tables[0].handle != tables[1].handle


def test_a_freed_table_handle_is_refused_even_when_its_slot_is_reused():
    table = parabola_table(2.0e8, 1.6, 0.5)
    handle = table.handle
    del table
    gc.collect()
    theta = np.zeros(1)
    assert _kernel.contact_table_evaluate(handle=handle, max_pairs=3, theta=theta)[-1] == (
        HANDLE_NOT_LIVE
    )
    newer = parabola_table(9.0e8, 1.3, 0.8)  # takes the freed slot
    assert newer.handle != handle
    assert _kernel.contact_table_evaluate(handle=handle, max_pairs=3, theta=theta)[-1] == (
        HANDLE_NOT_LIVE
    )
    assert _kernel.contact_table_free(handle) == HANDLE_NOT_LIVE
    # output arrays of the wrong size are refused, not written past their end
    assert _kernel.contact_table_evaluate(handle=newer.handle, max_pairs=2, theta=theta)[-1] != 0


def test_a_pickled_table_gets_a_handle_of_its_own():
    table = parabola_table(2.0e8, 1.6, 0.5)
    handle = table.handle
    copy = pickle.loads(pickle.dumps(table))
    assert copy.handle != handle
    s = 0.3
    expected = parabola_mesh(s, 2.0e8, 1.6, 0.5)
    for each in (table, copy):
        assert each.evaluate(np.array([2 * math.pi * s]))["stiffness"][0] == pytest.approx(
            expected,
            rel=1e-12,  # as above: a few ulp
        )


def test_a_table_the_kernel_refuses_gets_no_handle():
    broken = dataclasses.replace(parabola_table(2.0e8, 2.5, 0.5), max_pairs=2)  # eps needs 3
    with pytest.raises(KernelError, match="too small"):
        broken.check()
    with pytest.raises(KernelError):
        broken.handle  # noqa: B018 (still refused: nothing was kept)


def oscillator(stiffness: float, mass: float, time_step: float) -> BandedNewmark:
    return BandedNewmark([[mass]], [[0.0]], [[stiffness]], time_step)


def discrete_cosine(x0: float, omega: float, time_step: float, n_steps: int) -> np.ndarray:
    """x_n of the average-acceleration rule for x'' + w^2 x = 0, x(0) = x0, x'(0) = 0."""
    shortened = 2 * math.atan(omega * time_step / 2) / time_step
    return x0 * np.cos(shortened * time_step * np.arange(n_steps + 1))


def test_problems_created_and_run_inside_another_run_leave_it_alone():
    """Run A; after its first chunk, create and run problem B and twenty tables (the
    kernel's registries grow past their first eight slots), free them, and let A go on."""
    time_step, n_steps, x0 = 1e-4, 3000, 1e-3
    a_stiffness, b_stiffness, mass = 4.0e6, 9.0e6, 2.0
    solver_a = oscillator(a_stiffness, mass, time_step)
    probes = [KernelProbe("x", "displacement", np.ones(1))]
    inner = {}

    def meanwhile(done: int, total: int) -> None:
        if inner:
            return
        tables = [parabola_table(1e8 * (k + 1), 1.5, 0.5) for k in range(20)]
        assert len({t.handle for t in tables}) == 20
        solver_b = oscillator(b_stiffness, mass, time_step)
        inner["b"] = solver_b.run(n_steps, probes, q0=np.array([x0]))
        inner["b_handle"] = solver_b._problem()
        del tables, solver_b
        gc.collect()

    result_a = solver_a.run(n_steps, probes, q0=np.array([x0]), progress=meanwhile)
    assert inner, "the progress callback ran"
    for result, stiffness in ((result_a, a_stiffness), (inner["b"], b_stiffness)):
        expected = discrete_cosine(x0, math.sqrt(stiffness / mass), time_step, n_steps)
        # round-off of 3000 steps of the recurrence, about n eps |x0|, well below 1e-12 m
        np.testing.assert_allclose(result.samples[0], expected, rtol=0, atol=1e-12)

    # B was garbage collected: its handle is refused; A's still runs
    state = {"kd": 0, "n_mesh": 1, "q": np.array([x0]), "v": np.zeros(1)}
    assert _kernel.transient_start(handle=inner["b_handle"], **state)[-1] == PROBLEM_NOT_LIVE
    assert _kernel.transient_start(handle=solver_a._problem(), **state)[-1] == 0
