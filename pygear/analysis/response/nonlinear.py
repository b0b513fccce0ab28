r"""Contact loss and backlash in the periodic steady state: AFT harmonic balance.

Where the linear balance (:mod:`.hill`) finds a mesh force going negative, the teeth
part in reality.  Each mesh then carries, along its deflection delta_m, the force of
the kernel's flank law (``fortran/flank_contact.f90``): with the compression
c = s_m delta_m and the normal backlash b_m (:func:`pygear.assembly.mesh_backlash.
line_of_action_backlash`),

    F_m = k_m(t) g(c),   g(c) = c (c > 0, drive flank), 0 (-b_m <= c <= 0, free
    flight), c + b_m (c < -b_m, coast flank),

the backlash law of Kahraman & Singh (1990, J. Sound Vib. 142(1), 49-75) with the
origin at drive-flank contact (their x - b, their gap 2b being b_m here); the coast
flank takes the drive flank's stiffness (the kernel's default coast phase offset 0).
The force along delta_m is p_m = s_m F_m.

Condensation.  Writing p_m = kbar_m delta_m + r_m(delta, t), the elastic equations of
:mod:`.system` read y'' + C_r y' + Lambda y + B^T r = f, so harmonic j of the mesh
deflections obeys, with the receptance G_j = B D_j^-1 B^T of :mod:`.hill`,

    delta_j + G_j r_j(delta) - B D_j^-1 f_j = 0,                             (3)

exact (no assumption on r); with r = dk(t) delta it is Hill's condensed system (2).

Unknowns are the real Fourier coefficients of every mesh deflection, harmonics 0..H:
delta_m(t) = a_0 + sum_k (a_k cos k omega t + b_k sin k omega t).  r_j follows by the
alternating frequency-time method (Cameron & Griffin 1989, J. Appl. Mech. 56(1),
149-154): the coefficients are synthesised at N equally spaced instants, the force law
evaluated there and the samples transformed back.  Newton's method takes the analytic
Jacobian I + G A diag(k g'(c) - kbar) E by the same transforms (E the synthesis and A
the analysis matrix), and :mod:`.continuation` follows the branch in omega by
pseudo-arclength, through the turning points of the softening jump (Kahraman & Singh
1990; Parker, Vijayakar & Imajo 2000, J. Sound Vib. 237(3), 435-455).  N = 2^p >=
8 (2H + 1) keeps the aliasing of the force's harmonics small; with a smooth force law
and no contact loss the products are exact and (3) is Hill's (2) to round-off.

Stability.  The force law is continuous in delta, so the linearisation about a periodic
orbit is the variational equation y'' + C_r y' + (Lambda + B^T diag(k g'(c(t)) - kbar)
B) y = 0 with the contact state's stiffness at each instant (no saltation matrix: the
vector field has no jump); its Floquet multipliers come from :mod:`.floquet`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...assembly.mesh_backlash import line_of_action_backlash
from ...errors import CaseError
from ...model.case import Case, Scene
from .floquet import DEFAULT_SEGMENTS, batched_expm, floquet_multipliers, segment_means
from .system import ResponseSystem

__all__ = ["BacklashLaw", "BacklashProblem", "case_law", "oscillator_system"]


@dataclass(frozen=True)
class BacklashLaw:
    """The flank law of every mesh: drive flank, free flight in the backlash, coast flank.

    Attributes
    ----------
    backlash : ndarray, shape (n_mesh,)
        b_m >= 0 along the line of action [m]; ``inf`` leaves the coast flank out.
    smoothing : float
        eps >= 0 [m]: each kink max(c, 0) is replaced by (c + sqrt(c^2 + eps^2)) / 2, a
        regularised contact (0: the kernel's exact law).
    mesh_damping : ndarray, shape (n_mesh,), optional
        c_m [N s/m]: the mesh's viscous damper (its share beta kbar_m of the linear
        model's Rayleigh damping), made to act only while the flanks touch, as the
        kernel's does: F_m gains c_m g'(c) dc/dt.  None: the damper stays on across the
        gap (Kahraman & Singh's model).  Needs ``smoothing`` > 0: the switched damper
        makes the force jump at contact, which Newton and the monodromy cannot take.
    """

    backlash: np.ndarray
    smoothing: float = 0.0
    mesh_damping: np.ndarray | None = None

    def __post_init__(self) -> None:
        damper = self.mesh_damping
        if damper is not None and np.any(np.asarray(damper) > 0) and not self.smoothing > 0:
            raise ValueError(
                "a mesh damper that parts with the teeth needs smoothing > 0 (its force "
                "jumps at contact otherwise)"
            )

    def shape(self, compression: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """g(c), g'(c) and g''(c) (0 for the exact law), arrays of shape (..., n_mesh)."""
        c = compression
        b = np.asarray(self.backlash, dtype=np.float64)
        eps = float(self.smoothing)
        finite = np.isfinite(b)
        coast = c + np.where(finite, b, 0.0)  # c + b_m, used only where b_m is finite
        if eps == 0.0:
            g = np.maximum(c, 0.0) + np.where(finite, np.minimum(coast, 0.0), 0.0)
            slope = (c > 0).astype(np.float64) + (finite & (coast < 0))
            return g, slope, np.zeros_like(g)
        root = np.sqrt(c * c + eps * eps)
        root_b = np.sqrt(coast * coast + eps * eps)
        g = 0.5 * (c + root) + np.where(finite, 0.5 * (coast - root_b), 0.0)
        slope = 0.5 * (1 + c / root) + np.where(finite, 0.5 * (1 - coast / root_b), 0.0)
        bend = 0.5 * eps * eps * (1 / root**3 - np.where(finite, 1 / root_b**3, 0.0))
        return g, slope, bend


def oscillator_system(
    damping_ratio: float = 0.05,
    mean_force: float = 0.1,
    alternating_force: float = 0.0,
    stiffness_variation: tuple[float, ...] = (),
    samples: int = 1024,
) -> ResponseSystem:
    """The single-DOF spur pair of Kahraman & Singh (1990), nondimensional.

    x'' + 2 zeta x' + k(t) g(x) = F_m + F_a cos(omega t), k(t) = 1 + sum_j alpha_j
    cos(j omega t), unit mass and mean stiffness (natural frequency 1 rad/s), x the
    dynamic transmission error along the line of action (positive pressing the drive
    flanks).  ``speed`` in the response's datasets is then omega itself.

    Parameters
    ----------
    damping_ratio : float
        zeta.
    mean_force, alternating_force : float
        F_m and F_a (the external excitation, e.g. of a static transmission error).
    stiffness_variation : tuple of float
        alpha_1, alpha_2, ...: the mesh stiffness harmonics.
    samples : int
        Stiffness samples per period.
    """
    tau = np.arange(samples) / samples
    k = np.ones(samples)
    for j, alpha in enumerate(stiffness_variation, start=1):
        k += alpha * np.cos(2 * math.pi * j * tau)
    harmonic = None
    if alternating_force:
        harmonic = np.array([[0.5 * alternating_force]], dtype=complex)
    return ResponseSystem(
        eigenvalues=np.array([1.0]),
        damping=np.array([[2.0 * damping_ratio]]),
        mesh_rows=np.array([[1.0]]),
        force=np.array([float(mean_force)]),
        mean_stiffness=np.array([1.0]),
        stiffness=k[:, None],
        contact_sign=np.array([1], dtype=np.int64),
        mesh_order=np.array([1], dtype=np.int64),
        fundamental_per_rad_s=30.0 / (2 * math.pi**2),  # omega [rad/s] = speed [rpm]
        names=["pair"],
        stages=["pair"],
        planets=[0],
        modes=np.eye(1),
        attrs={"case": "Kahraman-Singh oscillator", "drive_torque": float(mean_force)},
        harmonic_force=harmonic,
    )


def _basis(harmonics: int, samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Real synthesis E (samples, 2H+1) and analysis A (2H+1, samples) matrices over
    [1, cos k theta, ..., sin k theta, ...], theta_n = 2 pi n / samples, and E' = dE /
    dtheta (the rate is omega E' x)."""
    theta = 2 * math.pi * np.arange(samples) / samples
    k = np.arange(1, harmonics + 1)
    phase = np.outer(theta, k)
    cos, sin = np.cos(phase), np.sin(phase)
    synthesis = np.concatenate([np.ones((samples, 1)), cos, sin], axis=1)
    analysis = synthesis.T * (2.0 / samples)
    analysis[0] *= 0.5
    rate = np.concatenate([np.zeros((samples, 1)), -k * sin, k * cos], axis=1)
    return synthesis, analysis, rate


def _resample(values: np.ndarray, count: int) -> np.ndarray:
    """Periodic samples (N, ...) at ``count`` equally spaced instants (every N/count-th
    sample, else by Fourier interpolation)."""
    n = values.shape[0]
    if n % count == 0:
        return np.ascontiguousarray(values[:: n // count])
    spectrum = np.fft.rfft(values, axis=0)
    return np.fft.irfft(spectrum[: count // 2 + 1], count, axis=0) * count / n


class BacklashProblem:
    """The AFT residual (3) of a :class:`ResponseSystem` with a backlash law.

    Parameters
    ----------
    system : ResponseSystem
        The linear model (its stiffness samples, receptances and loads).
    law : BacklashLaw
        The flank law of every mesh.
    harmonics : int
        H >= 1.
    samples : int, optional
        N, time samples of the AFT (default the power of two >= 8 (2H + 1)).
    """

    def __init__(
        self,
        system: ResponseSystem,
        law: BacklashLaw,
        harmonics: int,
        samples: int | None = None,
    ) -> None:
        self.system = system
        self.law = law
        self.harmonics = h = int(harmonics)
        if h < 1:
            raise ValueError("the AFT balance needs at least one harmonic")
        n = samples or 2 ** math.ceil(math.log2(8 * (2 * h + 1)))
        if n <= 2 * h:
            raise ValueError(f"{n} samples cannot resolve harmonic {h}")
        self.samples = n
        self.synthesis, self.analysis, self.rate = _basis(h, n)
        self.stiffness = _resample(np.asarray(system.stiffness, dtype=np.float64), n)
        self.sign = np.asarray(system.contact_sign, dtype=np.float64)
        self.n_mesh = system.mesh_rows.shape[0]
        damper = law.mesh_damping
        self.damper = np.zeros(self.n_mesh) if damper is None else np.asarray(damper, float)
        self._cache: tuple | None = None

    @property
    def size(self) -> int:
        """Unknowns: n_mesh (2H + 1)."""
        return self.n_mesh * (2 * self.harmonics + 1)

    def _forcing(self) -> np.ndarray:
        """f_j, j = 0..H, in modal coordinates: the static load and the harmonic force."""
        s = self.system
        forcing = np.zeros((self.harmonics + 1, s.size), dtype=complex)
        forcing[0] = s.force
        if s.harmonic_force is not None:
            extra = s.harmonic_force[: self.harmonics]
            forcing[1 : 1 + extra.shape[0]] = extra
        return forcing

    # -- frequency-domain operators ------------------------------------------------
    def operators(self, omega: float) -> tuple[np.ndarray, ...]:
        """Real receptance operator, load vector and their omega derivatives.

        Returns
        -------
        gain, gain_dw : ndarray, shape (2H+1, n_mesh, 2H+1, n_mesh)
            The real form of G_j acting on the real Fourier coefficients of r.
        load, load_dw : ndarray, shape (2H+1, n_mesh)
            Real Fourier coefficients of B D_j^-1 f_j.
        """
        if self._cache is not None and self._cache[0] == omega:
            return self._cache[1]
        s = self.system
        h, nm = self.harmonics, self.n_mesh
        rows, lam, c = s.mesh_rows, s.eigenvalues, s.damping
        forcing = self._forcing()
        j = np.arange(h + 1)[:, None, None]
        ident = np.eye(lam.size)[None]
        d = np.diag(lam)[None] - (j * omega) ** 2 * ident + 1j * j * omega * c[None]
        d_dw = -2 * j * j * omega * ident + 1j * j * c[None]
        right = np.concatenate(
            [np.broadcast_to(rows.T, (h + 1, *rows.T.shape)), forcing[:, :, None]], axis=2
        )
        solved = np.linalg.solve(d, right)  # D_j^-1 [B^T, f_j]
        solved_dw = -np.linalg.solve(d, d_dw @ solved)
        both = rows[None] @ solved  # (h+1, n_mesh, n_mesh + 1)
        both_dw = rows[None] @ solved_dw
        gain = np.zeros((2 * h + 1, nm, 2 * h + 1, nm))
        gain_dw = np.zeros_like(gain)
        load = np.zeros((2 * h + 1, nm))
        load_dw = np.zeros_like(load)
        k = np.arange(1, h + 1)
        for out, vec, mat in ((gain, load, both), (gain_dw, load_dw, both_dw)):
            g, w = mat[:, :, :nm], mat[:, :, nm]
            out[0, :, 0, :] = g[0].real
            vec[0] = w[0].real
            out[k, :, k, :] = g[1:].real
            out[k, :, h + k, :] = g[1:].imag
            out[h + k, :, k, :] = -g[1:].imag
            out[h + k, :, h + k, :] = g[1:].real
            vec[k], vec[h + k] = 2 * w[1:].real, -2 * w[1:].imag
        result = (gain, gain_dw, load, load_dw)
        self._cache = (omega, result)
        return result

    # -- time domain ---------------------------------------------------------------
    def signals(
        self, x: np.ndarray, samples: int | None = None, omega: float | None = None
    ) -> tuple[np.ndarray, ...]:
        """Mesh deflection, contact force and contact stiffness over one period.

        Parameters
        ----------
        x : ndarray
            Unknowns, flat or shape (2H+1, n_mesh).
        samples : int, optional
            Instants (default the AFT's N).
        omega : float, optional
            Fundamental [rad/s]: the switched mesh dampers' force joins the spring's.

        Returns
        -------
        deflection, force, slope : ndarray, shape (samples, n_mesh)
            delta_m [m]; F_m = k_m g(s_m delta_m) (+ c_m g' dc/dt) [N], > 0 on the
            drive flank, < 0 on the coast flank; k_m g'(c) [N/m].
        """
        coefficients = np.reshape(x, (2 * self.harmonics + 1, self.n_mesh))
        if samples is None or samples == self.samples:
            synthesis, rate, stiffness = self.synthesis, self.rate, self.stiffness
        else:
            synthesis, _, rate = _basis(self.harmonics, samples)
            stiffness = _resample(np.asarray(self.system.stiffness, dtype=np.float64), samples)
        deflection = synthesis @ coefficients
        g, dg, _ = self.law.shape(self.sign * deflection)
        force = stiffness * g
        if omega is not None and np.any(self.damper):
            force = force + self.damper * dg * self.sign * omega * (rate @ coefficients)
        return deflection, force, stiffness * dg

    def _local(
        self, x: np.ndarray, omega: float, synthesis: np.ndarray, rate: np.ndarray,
        stiffness: np.ndarray,
    ) -> tuple[np.ndarray, ...]:  # fmt: skip
        """r = p - kbar delta at the instants of ``synthesis``, its derivatives along
        delta and along its rate, and the rate over omega."""
        coefficients = np.reshape(x, (2 * self.harmonics + 1, self.n_mesh))
        deflection = synthesis @ coefficients
        g, dg, bend = self.law.shape(self.sign * deflection)
        kbar = self.system.mean_stiffness
        r = self.sign * stiffness * g - kbar * deflection
        along = stiffness * dg - kbar
        across = np.zeros_like(r)
        unit_rate = rate @ coefficients
        if np.any(self.damper):  # c_m (g'(c) - 1) delta': the damper off in the gap
            across = self.damper * (dg - 1)
            r = r + omega * across * unit_rate
            along = along + self.damper * bend * self.sign * omega * unit_rate
        return r, along, across, unit_rate

    def residual(self, x: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """R(x, omega) of (3), dR/dx and dR/domega (flat, length :attr:`size`)."""
        gain, gain_dw, load, load_dw = self.operators(omega)
        r, along, across, unit_rate = self._local(
            x, omega, self.synthesis, self.rate, self.stiffness
        )
        r_coeff = self.analysis @ r  # (2H+1, n_mesh)
        coefficients = np.reshape(x, r_coeff.shape)
        res = coefficients + np.einsum("imjl,jl->im", gain, r_coeff) - load
        a = self.analysis[:, None, :]
        local = (a * along.T[None]) @ self.synthesis  # dr_coeff/dx per mesh
        d_r = np.einsum("imjl,jl->im", gain_dw, r_coeff)
        if np.any(self.damper):  # the damper's rate omega E' x: along x and along omega
            local = local + omega * (a * across.T[None]) @ self.rate
            damper_r = self.analysis @ (across * unit_rate)
            d_r = d_r + np.einsum("imjl,jl->im", gain, damper_r)
        jac = np.einsum("imjl,jlk->imkl", gain, local)
        size = self.size
        jac = jac.reshape(size, size) + np.eye(size)
        return res.reshape(-1), jac, (d_r - load_dw).reshape(-1)

    def multipliers(
        self, x: np.ndarray, omega: float, segments: int = DEFAULT_SEGMENTS
    ) -> np.ndarray:
        """Floquet multipliers of the orbit x at omega, largest modulus first.

        The variational equation's stiffness Lambda + B^T diag(dr/ddelta + kbar) B (and,
        with switched mesh dampers, its damping C_r + B^T diag(c_m (g' - 1)) B) is
        averaged over each of ``segments`` intervals from 16 instants per interval
        (the contact switches inside an interval enter through the mean).
        """
        count = segments * 16
        synthesis, _, rate = _basis(self.harmonics, count)
        stiffness = _resample(np.asarray(self.system.stiffness, dtype=np.float64), count)
        _, along, across, _ = self._local(x, omega, synthesis, rate, stiffness)
        rows = self.system.mesh_rows
        stiff = np.diag(self.system.eigenvalues)[None] + np.einsum(
            "mi,sm,mj->sij", rows, segment_means(along, segments), rows
        )
        period = 2 * math.pi / omega
        if not np.any(self.damper):
            return floquet_multipliers(stiff, self.system.damping, period)
        damp = self.system.damping[None] + np.einsum(
            "mi,sm,mj->sij", rows, segment_means(across, segments), rows
        )
        n = rows.shape[1]
        a = np.zeros((segments, 2 * n, 2 * n))
        a[:, :n, n:] = np.eye(n)
        a[:, n:, :n] = -stiff
        a[:, n:, n:] = -damp
        product = np.eye(2 * n)
        for step in batched_expm(a * (period / segments)):
            product = step @ product
        values = np.linalg.eigvals(product)
        return values[np.argsort(-np.abs(values))]

    def modal_coefficients(self, x: np.ndarray, omega: float) -> np.ndarray:
        """Complex modal coefficients y_j, j = 0..H, of the orbit x (y(t) = y_0 + 2 Re
        sum_j y_j e^{i j omega t}): y_j = D_j^-1 (f_j - B^T r_j), shape (H + 1, n)."""
        s = self.system
        h = self.harmonics
        r = self.analysis @ self._local(x, omega, self.synthesis, self.rate, self.stiffness)[0]
        r_complex = np.zeros((h + 1, self.n_mesh), dtype=complex)
        r_complex[0] = r[0]
        r_complex[1:] = 0.5 * (r[1 : h + 1] - 1j * r[h + 1 :])
        forcing = self._forcing()
        j = np.arange(h + 1)[:, None, None]
        d = (
            np.diag(s.eigenvalues)[None]
            - (j * omega) ** 2 * np.eye(s.size)[None]
            + 1j * j * omega * s.damping[None]
        )
        rhs = forcing - r_complex @ s.mesh_rows
        return np.linalg.solve(d, rhs[..., None])[..., 0]

    def summary(self, x: np.ndarray, samples: int, omega: float | None = None) -> dict:
        """Per-mesh force extremes and mean, DTE RMS and peak to peak, and whether the
        drive flanks part (``separation``) or the coast flanks meet (``coast``), read
        at ``samples`` instants of the period."""
        deflection, force, _ = self.signals(x, samples, omega)
        compression = self.sign * deflection
        dte = deflection - deflection.mean(axis=0)
        return {
            "force_max": force.max(axis=0),
            "force_min": force.min(axis=0),
            "force_mean": force.mean(axis=0),
            "dte_rms": np.sqrt((dte**2).mean(axis=0)),
            "dte_pp": deflection.max(axis=0) - deflection.min(axis=0),
            "separation": (compression <= 0).any(axis=0),
            "coast": (compression < -np.asarray(self.law.backlash)).any(axis=0),
        }

    def linear_solution(self, omega: float) -> np.ndarray:
        """The balance with every mesh's flanks held together (the flank law with b = 0
        is g(c) = c): one Newton step from any start solves it exactly."""
        linear = BacklashProblem(
            self.system, BacklashLaw(np.zeros(self.n_mesh)), self.harmonics, self.samples
        )
        x = linear.static_guess()
        r, jac, _ = linear.residual(x, omega)
        return x - np.linalg.solve(jac, r)

    def static_guess(self) -> np.ndarray:
        """The static deflection at mean stiffness as a start (harmonics 1..H zero)."""
        x = np.zeros((2 * self.harmonics + 1, self.n_mesh))
        x[0] = self.system.static_deflection()
        return x.reshape(-1)

    def from_hill(self, deflection: np.ndarray) -> np.ndarray:
        """Unknowns from complex coefficients over -H'..H' (:class:`.hill.HillSolution`),
        truncated or padded to H."""
        centre = deflection.shape[0] // 2
        h = self.harmonics
        top = min(h, centre)
        x = np.zeros((2 * h + 1, self.n_mesh))
        x[0] = deflection[centre].real
        x[1 : top + 1] = 2 * deflection[centre + 1 : centre + top + 1].real
        x[h + 1 : h + top + 1] = -2 * deflection[centre + 1 : centre + top + 1].imag
        return x.reshape(-1)


def case_law(
    case: Case,
    system: ResponseSystem,
    scene: Scene | None = None,
    smoothing: float = 0.0,
    *,
    switched_dampers: bool = False,
) -> BacklashLaw:
    """The flank law of a case's meshes: the normal backlash the kernel's
    ``tooth_separation`` effect uses (:func:`.line_of_action_backlash`).

    Parameters
    ----------
    case : Case
        The case the system was built from.
    system : ResponseSystem
        Its response model (the assembled meshes, in order).
    scene : Scene, optional
        The scene whose parameter changes apply (as given to :func:`.response_system`).
    smoothing : float
        Regularisation of the contact kinks [m] (:class:`BacklashLaw`).
    switched_dampers : bool
        Each mesh's damper (beta kbar_m, :class:`.MeshElement`) acts only while its
        flanks touch, as in the kernel's transient; needs ``smoothing`` > 0 (a small
        share of the static mesh deflection, e.g. 1 %).

    Raises
    ------
    CaseError
        A mesh has no backlash.
    """
    if system.model is None:
        raise CaseError("the response system carries no assembled model to read meshes from")
    seen = case.for_scene(scene) if scene is not None else case
    backlash = line_of_action_backlash(seen, system.model, "tooth_separation")
    dampers = None
    if switched_dampers:
        dampers = np.array([m.damping for m in system.model.meshes], dtype=np.float64)
    return BacklashLaw(backlash, smoothing, dampers)
