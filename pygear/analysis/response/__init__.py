"""The periodic steady state at constant speed: dynamic factors, load sharing, stability.

- :mod:`.system`: the linear time-periodic model of a case at constant speed, in elastic
  modal form, with each mesh's stiffness sampled over one period;
- :mod:`.hill`: harmonic balance (Hill's method), its sparse block matrix and the mesh
  signals rebuilt from a solution;
- :mod:`.floquet`: Floquet multipliers from the monodromy matrix;
- :mod:`.sweep`: the response over a speed range as an ``xarray.Dataset``.
"""

from .floquet import floquet_multipliers, system_multipliers
from .hill import HillSolution, harmonic_balance, hill_matrix, mesh_signals, solve_hill
from .sweep import forced_response, response_summary, sweep_system
from .system import ResponseSystem, response_system

__all__ = [
    "HillSolution",
    "ResponseSystem",
    "floquet_multipliers",
    "forced_response",
    "harmonic_balance",
    "hill_matrix",
    "mesh_signals",
    "response_summary",
    "response_system",
    "solve_hill",
    "sweep_system",
    "system_multipliers",
]
