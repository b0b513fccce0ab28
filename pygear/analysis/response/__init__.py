"""The periodic steady state at constant speed: dynamic factors, load sharing, stability.

- :mod:`.system`: the linear time-periodic model of a case at constant speed, in elastic
  modal form, with each mesh's stiffness sampled over one period;
- :mod:`.hill`: harmonic balance (Hill's method), its sparse block matrix and the mesh
  signals rebuilt from a solution;
- :mod:`.floquet`: Floquet multipliers from the monodromy matrix;
- :mod:`.quasi` and :mod:`.quasi_sweep`: the multi-frequency balance of gearboxes whose
  stages mesh at incommensurate frequencies, on a lattice of combination frequencies;
- :mod:`.sweep`: the response over a speed range as an ``xarray.Dataset``;
- :mod:`.operating`: the dynamic factor per mesh at one speed, for a rating;
- :mod:`.nonlinear` and :mod:`.continuation`: contact loss with backlash, continued in
  speed through the folds.
"""

from .continuation import continue_response, separated_response
from .floquet import floquet_multipliers, system_multipliers
from .hill import HillSolution, harmonic_balance, hill_matrix, mesh_signals, solve_hill
from .nonlinear import BacklashLaw, case_law, oscillator_system
from .operating import dynamic_factors_at
from .quasi import QuasiSolution, solve_quasi
from .sweep import (
    branch_jumps,
    contact_loss_response,
    forced_response,
    response_summary,
    scene_response,
    sweep_system,
)
from .system import ResponseSystem, response_system

__all__ = [
    "BacklashLaw",
    "HillSolution",
    "QuasiSolution",
    "ResponseSystem",
    "branch_jumps",
    "case_law",
    "contact_loss_response",
    "continue_response",
    "dynamic_factors_at",
    "floquet_multipliers",
    "forced_response",
    "harmonic_balance",
    "hill_matrix",
    "mesh_signals",
    "oscillator_system",
    "response_summary",
    "response_system",
    "scene_response",
    "separated_response",
    "solve_hill",
    "solve_quasi",
    "sweep_system",
    "system_multipliers",
]
