"""The kernel's reverse Cuthill-McKee ordering on patterns whose best band is known."""

from __future__ import annotations

import numpy as np
import pytest

from pygear.kernel.band_ordering import band_half_width, reverse_cuthill_mckee


def _pattern(n: int, edges) -> np.ndarray:
    pattern = np.eye(n, dtype=bool)
    for i, j in edges:
        pattern[i, j] = pattern[j, i] = True
    return pattern


@pytest.mark.parametrize("seed", range(5))
def test_scrambled_chain_gets_band_one(seed):
    """A chain's best band is 1; Cuthill-McKee from an end walks it in order."""
    n = 40
    labels = np.random.default_rng(seed).permutation(n)
    pattern = _pattern(n, [(labels[k], labels[k + 1]) for k in range(n - 1)])
    order = reverse_cuthill_mckee(pattern)
    assert sorted(order) == list(range(n))
    assert band_half_width(pattern, order) == 1


@pytest.mark.parametrize("rows, columns", [(4, 10), (6, 6), (3, 20)])
def test_scrambled_grid_gets_its_short_side(rows, columns):
    """A rows x columns grid graph: level sets from a corner are anti-diagonals, so the
    band is at most the short side (the best possible for a grid is min(rows, columns))."""
    index = np.arange(rows * columns).reshape(rows, columns)
    edges = [(index[r, c], index[r, c + 1]) for r in range(rows) for c in range(columns - 1)]
    edges += [(index[r, c], index[r + 1, c]) for r in range(rows - 1) for c in range(columns)]
    labels = np.random.default_rng(1).permutation(rows * columns)
    pattern = _pattern(rows * columns, [(labels[i], labels[j]) for i, j in edges])
    order = reverse_cuthill_mckee(pattern)
    assert min(rows, columns) <= band_half_width(pattern, order) <= min(rows, columns) + 1


def test_components_and_isolated_nodes_are_all_ordered():
    pattern = _pattern(7, [(0, 3), (3, 5), (1, 6)])  # {0,3,5}, {1,6}, {2}, {4}
    order = reverse_cuthill_mckee(pattern)
    assert sorted(order) == list(range(7))
    assert band_half_width(pattern, order) == 1
