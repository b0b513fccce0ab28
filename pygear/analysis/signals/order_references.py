"""The references of order tracking: a member's angle in a run, and the mesh orders of
every stage relative to a member.

**Angle.**  A run keeps what its probes ask for.  A member's angle is its ``theta_z``
displacement, ``Probe("displacement", "planetary.carrier.theta_z")`` (rad; the kernel
adds back the rigid rotation it rebases, so the channel is the whole angle).  Without
one, the angle is the trapezoid integral of the member's speed channel,
``Probe("speed", "planetary.carrier")`` (rpm).  With the average-acceleration Newmark
integrator (beta = 1/4, gamma = 1/2) and one output sample per step, the kernel's own
displacement update is q_{n+1} - q_n = h v_n + (h^2/4)(a_n + a_{n+1}) = (h/2)(v_n +
v_{n+1}): the trapezoid rule on its velocities, so the integral equals the displacement
to round-off.  With H = decimation x time step between output samples, the trapezoid
sum exceeds the angle by (H^2/12)[omega'(T) - omega'(0)] + O(H^4) at time T
(Euler-Maclaurin): the study case's run-up at a quarter of its output rate (H = 1e-4 s,
omega' varying by about 1e3 rad/s^2 with the mesh vibration) is off by 8e-7 rad.

**Mesh orders.**  A stage's mesh frequency over the reference's rotation frequency:
Z_r |n_c - n_r| / |n_ref| for a planetary stage (relative to the carrier with the ring
held, the ring's tooth number), Z_1 |n_1| / |n_ref| for a parallel pair.  A rigid gear
train keeps every speed ratio, so the order is the same at every speed of a run-up.
:func:`mesh_orders` takes the ratios from the assembled model's rigid-body rotation;
:func:`stored_mesh_orders` from a run file's mesh frequencies and equilibrium speeds, so
that analysing a file never loads a case.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...assembly.dof_rows import dof_row, rigid_rotation
from ...assembly.matrices import Model
from ...errors import CaseError
from ...model.case import Case
from .channels import channel_series, run_channels
from .signal import SignalError

__all__ = [
    "AngleReference",
    "mesh_orders",
    "reference_angle",
    "reference_members",
    "stored_mesh_orders",
]

RAD_S_PER_RPM = math.pi / 30.0


@dataclass(frozen=True)
class AngleReference:
    """A member's angle through a run, along its running sense.

    Attributes
    ----------
    member : str
        The member (a probe target such as ``planetary.carrier``).
    time : numpy.ndarray
        Sample times [s].
    angle : numpy.ndarray
        Angle [rad], increasing when the member turns in its running sense.
    speed : numpy.ndarray
        d angle / dt [rad/s].
    source : str
        Where the angle comes from (a channel, or the integral of one).
    sense : int
        +1, or -1 when the member runs along -theta_z (a negative drive).
    """

    member: str
    time: np.ndarray
    angle: np.ndarray
    speed: np.ndarray
    source: str
    sense: int


def reference_members(run: xr.Dataset) -> dict[str, dict[str, str]]:
    """Members with an angle or speed channel: ``{member: {"angle": name, "speed": name}}``
    (channel names, :mod:`pygear.analysis.signals.channels`).

    Channels are recognised by their kind and label (``speed:<stage.member>``, the
    ``displacement`` of ``<stage.member>.theta_z``) or, for a named probe's variable, by
    the attributes pygear's probes write (``quantity``, ``target``, ``units``).
    """
    found: dict[str, dict[str, str]] = {}
    for name, (variable, _, label) in run_channels(run).items():
        attrs = run[variable].attrs
        quantity = attrs.get("quantity")
        target = str(label if label is not None else attrs.get("target", ""))
        units = str(attrs.get("units", ""))
        if quantity == "speed" and units == "rpm" and target:
            found.setdefault(target, {}).setdefault("speed", name)
        elif quantity == "displacement" and units == "rad" and target.endswith(".theta_z"):
            found.setdefault(target.removesuffix(".theta_z"), {}).setdefault("angle", name)
    return found


def _match(members: dict, member: str) -> str:
    if member in members:
        return member
    suffix = [m for m in members if m.endswith(f".{member}")]
    if len(suffix) == 1:
        return suffix[0]
    known = ", ".join(sorted(members)) or "none"
    rule = "names several members" if suffix else "is not a member with a speed or angle channel"
    raise SignalError(
        f"--orders {member!r} {rule} in this run (members: {known}); a run records a "
        'member\'s angle with Probe("displacement", "<stage>.<member>.theta_z") or its '
        'speed with Probe("speed", "<stage>.<member>")'
    )


def _series(run: xr.Dataset, name: str, what: str) -> np.ndarray:
    values = np.asarray(channel_series(run, name).values, dtype=float)
    if not np.all(np.isfinite(values)):
        raise SignalError(f"--orders: the {what} channel {name!r} holds NaN or inf")
    return values


def reference_angle(run: xr.Dataset, member: str) -> AngleReference:
    """The angle and speed of ``member`` over the run, along its running sense.

    Parameters
    ----------
    run : xarray.Dataset
        A run with probe channels along ``time``.
    member : str
        ``stage.member`` (``planetary.carrier``) or, when unique, the member alone.

    Raises
    ------
    SignalError
        No such member, no angle or speed channel for it, or a bad time coordinate.
    """
    members = reference_members(run)
    member = _match(members, member)
    channels = members[member]
    time = np.asarray(run["time"].values, dtype=float) if "time" in run.coords else None
    if time is None or time.size < 4:
        raise SignalError("time: the run needs a time coordinate of at least 4 samples [s]")
    if not (np.all(np.isfinite(time)) and np.all(np.diff(time) > 0)):
        raise SignalError("time: the run's time coordinate must be finite and strictly increasing")
    speed = None
    if "speed" in channels:
        speed = _series(run, channels["speed"], "speed") * RAD_S_PER_RPM
    if "angle" in channels:
        angle = _series(run, channels["angle"], "angle")
        source = f"angle channel {channels['angle']}"
        if speed is None:
            from scipy.interpolate import make_interp_spline

            speed = make_interp_spline(time, angle, k=3).derivative()(time)
    else:
        steps = np.diff(time) * 0.5 * (speed[1:] + speed[:-1])
        angle = np.concatenate(([0.0], np.cumsum(steps)))
        source = f"trapezoid integral of speed channel {channels['speed']}"
    sense = -1 if speed[int(np.argmax(np.abs(speed)))] < 0 else 1
    return AngleReference(member, time, sense * angle, sense * speed, source, sense)


def _equilibrium_speed(run: xr.Dataset, member: str) -> float | None:
    if "equilibrium_speed" not in run or "body" not in run.coords:
        return None
    for key, value in zip(run["body"].values.tolist(), run["equilibrium_speed"].values):
        if key == member or ("." not in key and member.endswith(f".{key}")):
            return float(value)
    return None


def stored_mesh_orders(run: xr.Dataset, member: str) -> dict[str, float]:
    """Mesh order of each stage relative to ``member``, from a run file alone.

    The mesh frequencies ``pygear run`` stores (at the equilibrium speeds) over the
    member's equilibrium rotation frequency.  Empty when the file holds neither.

    Parameters
    ----------
    run : xarray.Dataset
        A ``pygear run`` file with ``mesh_frequency`` over ``mesh_stage`` and
        ``equilibrium_speed`` over ``body``.
    member : str
        The reference member (``planetary.carrier``).

    Returns
    -------
    dict of str to float
        ``{stage: order}``.
    """
    speed = _equilibrium_speed(run, member)
    if speed is None or "mesh_frequency" not in run or not abs(speed) > 0.0:
        return {}
    return {
        str(stage): float(frequency) * 60.0 / abs(speed)
        for stage, frequency in zip(run["mesh_stage"].values, run["mesh_frequency"].values)
        if np.isfinite(frequency)
    }


def mesh_orders(
    case: Case, model: Model, member: str, *, per_mesh: bool = False
) -> dict[str, float]:
    """Mesh order of each stage (or each mesh) relative to ``member``, from the model's
    kinematics.

    Speed ratios are those of the free rigid-body rotation of the assembled model (the
    zero mode of K0 and M), so a held ring, rigid links and every stage of a gearbox
    are taken into account.  The speeds follow the base radii and the mesh cycles the
    tooth numbers, so a planetary stage whose Z_r / Z_s differs from r_br / r_bs has two
    mesh orders: the sun-planet meshes at Z_s |n_s - n_c| / |n_ref|, the ring-planet
    meshes at Z_r |n_c - n_r| / |n_ref|.

    Parameters
    ----------
    case : Case
        The case (stages and tooth numbers).
    model : Model
        Its assembled model.
    member : str
        ``stage.member`` whose revolutions count the orders (``planetary.carrier``).
    per_mesh : bool
        Give each mesh's order (``stage.sun-planet``, ``stage.ring-planet``,
        ``stage.mesh`` of a parallel pair) instead of the stage's (its ring-planet
        mesh, as the run files' mesh frequencies count it).

    Returns
    -------
    dict of str to float
        ``{stage: order}`` (or ``{stage.mesh: order}``) for the gears with tooth numbers.

    Raises
    ------
    CaseError
        An unknown member, one that does not turn in the rigid-body rotation, or a
        model without exactly one free rotation.
    """
    rotation = rigid_rotation(model)
    if rotation is None:
        raise CaseError(
            f"member: the model of {case.name!r} has no single free rotation, so its speed "
            "ratios (and mesh orders) are not defined"
        )

    def speed(label: str) -> float:
        row = dof_row(model, f"{label}.theta_z")
        if row is None:
            raise CaseError(f"member: {label!r} is not a member of {case.name!r}")
        return float(row @ rotation)

    reference = speed(member)
    if not abs(reference) > 1e-9 * float(np.max(np.abs(rotation))):
        raise CaseError(f"member: {member!r} does not turn in the gearbox's rigid rotation")
    orders = {}
    for stage in case.gearbox.stages:
        name, kind = stage.name, getattr(stage, "kind", "")
        if kind == "planetary":
            carrier = speed(f"{name}.carrier")
            if per_mesh and stage.sun.teeth:
                relative = speed(f"{name}.sun") - carrier
                orders[f"{name}.sun-planet"] = stage.sun.teeth * abs(relative / reference)
            if stage.ring.teeth:
                relative = carrier - speed(f"{name}.ring")
                key = f"{name}.ring-planet" if per_mesh else name
                orders[key] = stage.ring.teeth * abs(relative / reference)
        elif kind == "parallel" and stage.input_gear.teeth:
            turning = speed(f"{name}.input_gear")
            key = f"{name}.mesh" if per_mesh else name
            orders[key] = stage.input_gear.teeth * abs(turning / reference)
    return orders
