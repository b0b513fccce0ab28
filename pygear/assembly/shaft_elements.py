"""Element matrices of flexible drivetrains: shafts, discs, bearings and couplings.

The matrices come from the Fortran module ``shaft_elements`` (docs/shaft_elements.md);
this module checks the arguments, so that a bad value ends as a one-line
:class:`~pygear.errors.CaseError` naming the parameter, and wraps the result in
:class:`ElementMatrices`.

Node DOFs are x, y, z, theta_x, theta_y, theta_z with the shaft axis along z (SI
units, rad).  In the right-handed frame a positive theta_y turns the shaft axis towards
+x and a positive theta_x turns it towards -y.  The equations of motion are
``M q'' + (C + Omega G) q' + K q = F`` with G the gyroscopic matrix per unit spin speed
Omega [rad/s] about +z.

Sources: Nelson (1980), "A finite rotating shaft element using Timoshenko beam
theory", J. Mech. Des. 102, 793-803; Friswell, Penny, Garvey & Lees (2010), "Dynamics of
Rotating Machines", Cambridge University Press, chapter 5; Hutchinson (2001), "Shear
coefficients for Timoshenko beam theory", J. Appl. Mech. 68, 87-92.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError
from ..kernel.calls import call
from ..model.components import require_non_negative, require_positive

__all__ = [
    "DEFAULT_POISSON_RATIO",
    "ElementMatrices",
    "bearing_element",
    "coupling_element",
    "disc_element",
    "shaft_element",
    "shear_coefficient",
]

DEFAULT_POISSON_RATIO = 0.3
"""Poisson's ratio of steel, giving the shear modulus E / (2 (1 + nu)) when none is given."""


@dataclass(frozen=True)
class ElementMatrices:
    """Matrices of one element, all of the same square size (6 for one node, 12 for two).

    Attributes
    ----------
    mass : ndarray
        Mass matrix M [kg, kg m, kg m^2].
    stiffness : ndarray
        Stiffness matrix K [N/m, N/rad, N m/rad].
    damping : ndarray
        Viscous damping matrix C [N s/m, N m s/rad].
    gyroscopic : ndarray
        Gyroscopic matrix G per unit spin speed [kg m^2], skew-symmetric; the element
        adds ``Omega G q'`` to the equations of motion.

    The arrays are read-only, so one instance may be placed many times.
    """

    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    gyroscopic: np.ndarray

    def __post_init__(self) -> None:
        size = None
        for name in ("mass", "stiffness", "damping", "gyroscopic"):
            array = np.array(getattr(self, name), dtype=float)
            if array.ndim != 2 or array.shape[0] != array.shape[1] or array.shape[0] not in (6, 12):
                raise CaseError(f"{name} must be a 6 x 6 or 12 x 12 matrix (got {array.shape})")
            if size is not None and array.shape[0] != size:
                raise CaseError(f"{name} must have the size of mass ({size} x {size})")
            size = array.shape[0]
            array.flags.writeable = False
            object.__setattr__(self, name, array)

    @property
    def size(self) -> int:
        """Number of DOFs: 6 (one node) or 12 (two nodes)."""
        return int(self.mass.shape[0])

    @property
    def node_count(self) -> int:
        """Number of nodes the element connects: 1 or 2."""
        return self.size // 6


def shear_coefficient(outer_diameter: float, inner_diameter: float, poisson_ratio: float) -> float:
    """Timoshenko shear coefficient of a hollow circular section (Hutchinson 2001).

    Parameters
    ----------
    outer_diameter, inner_diameter : float
        Diameters D > d >= 0 [m].
    poisson_ratio : float
        nu, -1 < nu <= 0.5 [-].

    Returns
    -------
    float
        kappa = 6 (a^2 + b^2)^2 (1 + nu)^2 / [7 a^4 + 34 a^2 b^2 + 7 b^4
        + nu (12 a^4 + 48 a^2 b^2 + 12 b^4) + nu^2 (4 a^4 + 16 a^2 b^2 + 4 b^4)]
        with a = D/2, b = d/2 (Hutchinson 2001, the hollow circle); 0.9252 for a solid
        steel section (nu = 0.3).
    """
    _check_section(outer_diameter, inner_diameter)
    if not (math.isfinite(poisson_ratio) and -1.0 < poisson_ratio <= 0.5):
        raise CaseError(f"poisson_ratio must lie in (-1, 0.5] (got {poisson_ratio!r})")
    (kappa,) = call("shaft_shear_coefficient", outer_diameter, inner_diameter, poisson_ratio)
    return float(kappa)


_shear_coefficient = shear_coefficient  # shaft_element's argument of the same name hides it


def shaft_element(
    length: float,
    outer_diameter: float,
    inner_diameter: float = 0.0,
    youngs_modulus: float = 2.1e11,
    shear_modulus: float | None = None,
    density: float = 7850.0,
    shear_deformation: bool = True,
    shear_coefficient: float | None = None,
    rotary_inertia: bool = True,
) -> ElementMatrices:
    """Timoshenko shaft element of a uniform hollow circular section, 2 nodes x 6 DOFs.

    Bending in the x-z and y-z planes with the shear parameter
    Phi = 12 E I / (kappa G A L^2) (Friswell et al. 2010, chapter 5), consistent mass
    with rotary inertia, the gyroscopic matrix per unit spin (Nelson 1980), and linear
    axial and torsional bars.

    Parameters
    ----------
    length : float
        Element length L [m].
    outer_diameter : float
        Outer diameter D [m].
    inner_diameter : float
        Bore diameter d, 0 <= d < D [m].
    youngs_modulus : float
        E [Pa].
    shear_modulus : float, optional
        G [Pa]; by default E / (2 (1 + 0.3)).
    density : float
        rho [kg/m^3].
    shear_deformation : bool
        False gives the Euler-Bernoulli stiffness (Phi = 0).
    shear_coefficient : float, optional
        kappa in (0, 1]; by default Hutchinson's (2001) value for the hollow circle with
        nu = E / (2 G) - 1.
    rotary_inertia : bool
        False leaves the rotary inertia of the bending rotations out of the mass matrix
        (the gyroscopic matrix keeps it).

    Returns
    -------
    ElementMatrices
        12 x 12 matrices over (node 1, node 2); damping zero.
    """
    require_positive("length", length)
    _check_section(outer_diameter, inner_diameter)
    require_positive("youngs_modulus", youngs_modulus)
    require_positive("density", density)
    if shear_modulus is None:
        shear_modulus = youngs_modulus / (2.0 * (1.0 + DEFAULT_POISSON_RATIO))
    require_positive("shear_modulus", shear_modulus)
    if shear_coefficient is None:
        poisson_ratio = youngs_modulus / (2.0 * shear_modulus) - 1.0
        if not -1.0 < poisson_ratio <= 0.5:
            raise CaseError(
                f"shear_modulus must give a Poisson's ratio E / (2 G) - 1 in (-1, 0.5] "
                f"(got {poisson_ratio:.4g})"
            )
        kappa = _shear_coefficient(outer_diameter, inner_diameter, poisson_ratio)
    else:
        kappa = shear_coefficient
        if not (_is_number(kappa) and 0.0 < kappa <= 1.0):
            raise CaseError(f"shear_coefficient must lie in (0, 1] (got {kappa!r})")
    mass, stiffness, gyroscopic = call(
        "shaft_element_matrices",
        length,
        outer_diameter,
        inner_diameter,
        youngs_modulus,
        shear_modulus,
        density,
        kappa,
        int(bool(shear_deformation)),
        int(bool(rotary_inertia)),
    )
    return ElementMatrices(mass, stiffness, np.zeros((12, 12)), gyroscopic)


def disc_element(mass: float, polar_inertia: float, diametral_inertia: float) -> ElementMatrices:
    """Rigid disc at one node.

    Parameters
    ----------
    mass : float
        m > 0 [kg].
    polar_inertia : float
        I_p about the shaft axis [kg m^2].
    diametral_inertia : float
        I_d about x and y through the disc centre [kg m^2].

    Returns
    -------
    ElementMatrices
        6 x 6: M = diag(m, m, m, I_d, I_d, I_p), G(theta_x, theta_y) = I_p =
        -G(theta_y, theta_x) (the disc's angular momentum I_p Omega along its tilted
        axis), K and C zero.
    """
    require_positive("mass", mass)
    require_non_negative("polar_inertia", polar_inertia)
    require_non_negative("diametral_inertia", diametral_inertia)
    mass_matrix, gyroscopic = call("disc_element_matrices", mass, polar_inertia, diametral_inertia)
    return ElementMatrices(mass_matrix, np.zeros((6, 6)), np.zeros((6, 6)), gyroscopic)


def bearing_element(
    stiffness: np.ndarray | list[float],
    damping: np.ndarray | list[float] | None = None,
    nodes: int = 1,
) -> ElementMatrices:
    """Bearing: a 6 x 6 stiffness and damping on a node's motion or on two nodes' relative motion.

    Parameters
    ----------
    stiffness : array_like
        6 values (the diagonal: x, y, z, theta_x, theta_y, theta_z, i.e. radial, radial,
        axial, tilt, tilt, torsional) or a full 6 x 6 matrix, symmetric or not
        (cross-coupled fluid-film coefficients) [N/m, N/rad, N m/rad]; diagonal >= 0.
    damping : array_like, optional
        The same shapes [N s/m, N m s/rad]; zero by default.
    nodes : int
        1: node to ground (6 x 6); 2: between two nodes, acting on q_1 - q_2 (12 x 12).

    Returns
    -------
    ElementMatrices
        Stiffness and damping; mass and gyroscopic zero.
    """
    stiffness_matrix = _bearing_matrix("stiffness", stiffness)
    damping_matrix = np.zeros((6, 6)) if damping is None else _bearing_matrix("damping", damping)
    if nodes not in (1, 2) or isinstance(nodes, bool):
        raise CaseError(f"nodes must be 1 (to ground) or 2 (between nodes) (got {nodes!r})")
    routine = "ground_bearing_matrices" if nodes == 1 else "node_bearing_matrices"
    k, c = call(routine, np.asfortranarray(stiffness_matrix), np.asfortranarray(damping_matrix))
    zeros = np.zeros_like(k)
    return ElementMatrices(zeros, k, c, zeros)


def coupling_element(
    torsional: float,
    radial: float = 0.0,
    axial: float = 0.0,
    angular: float = 0.0,
    torsional_damping: float = 0.0,
    radial_damping: float = 0.0,
    axial_damping: float = 0.0,
    angular_damping: float = 0.0,
) -> ElementMatrices:
    """Flexible coupling between two coincident nodes (12 x 12).

    Independent springs and dampers on the relative motion q_1 - q_2: radial on x and y,
    axial on z, angular (tilt) on theta_x and theta_y, torsional on theta_z.

    Parameters
    ----------
    torsional : float
        Torsional stiffness > 0 [N m/rad].
    radial, axial : float
        Radial and axial stiffness >= 0 [N/m].
    angular : float
        Angular stiffness >= 0 [N m/rad].
    torsional_damping, angular_damping : float
        >= 0 [N m s/rad].
    radial_damping, axial_damping : float
        >= 0 [N s/m].

    Returns
    -------
    ElementMatrices
        Stiffness and damping; mass and gyroscopic zero.
    """
    require_positive("torsional", torsional)
    values = {
        "radial": radial,
        "axial": axial,
        "angular": angular,
        "torsional_damping": torsional_damping,
        "radial_damping": radial_damping,
        "axial_damping": axial_damping,
        "angular_damping": angular_damping,
    }
    for name, value in values.items():
        require_non_negative(name, value)
    k, c = call(
        "coupling_element_matrices",
        torsional,
        radial,
        axial,
        angular,
        torsional_damping,
        radial_damping,
        axial_damping,
        angular_damping,
    )
    zeros = np.zeros((12, 12))
    return ElementMatrices(zeros, k, c, zeros)


def _is_number(value: object) -> bool:
    return (
        isinstance(value, (int, float, np.number))
        and not isinstance(value, bool)
        and (math.isfinite(value))
    )


def _check_section(outer_diameter: float, inner_diameter: float) -> None:
    require_positive("outer_diameter", outer_diameter)
    require_non_negative("inner_diameter", inner_diameter)
    if not inner_diameter < outer_diameter:
        raise CaseError(
            f"inner_diameter must be smaller than outer_diameter "
            f"(got {inner_diameter!r} >= {outer_diameter!r})"
        )


def _bearing_matrix(name: str, value: object) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise CaseError(f"{name} must be 6 numbers or a 6 x 6 matrix (got {value!r})") from None
    if array.shape == (6,):
        array = np.diag(array)
    if array.shape != (6, 6):
        raise CaseError(f"{name} must be 6 numbers or a 6 x 6 matrix (got shape {array.shape})")
    if not np.all(np.isfinite(array)):
        raise CaseError(f"{name} must hold finite numbers")
    if np.any(np.diag(array) < 0):
        raise CaseError(f"{name} must have a non-negative diagonal (got {np.diag(array)!r})")
    return array
