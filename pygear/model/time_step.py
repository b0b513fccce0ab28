"""Does a transient's time step resolve the gear meshes at the scene's speed?

The contact table samples each mesh's stiffness once per step and the integrator's
average-acceleration rule lengthens a period T by about (2 pi dt / T)^2 / 12, so a
step must be a small part of the shortest mesh period the run can reach.  A scene
whose step spans a whole mesh period or more (``steady_sensor`` typed at 1e7 rpm ran
with some 400 mesh periods per step) samples the mesh excitation at random and its
result means nothing; :func:`check_time_step` refuses it before any work.

The speeds a scene states are its ``initial_speed_rpm`` and its ``speed_reference_rpm``
(the run-up's target) at the gearbox's input member.  The mesh frequencies per input
turn follow the stages in their order from the input, the way pygear's shipped
gearboxes are built: a planetary stage with its ring held, carrier in and sun out
(Z_r mesh events per carrier turn, sun at 1 + Z_r/Z_s times the carrier), a parallel
pair from input to output gear (Z_in events per turn, output at r_b1/r_b2), an
inertia passing the speed on.  Where the gearbox's input is not the first stage's
(another power path), the rule is not applied.
"""

from __future__ import annotations

from ..errors import CaseError

__all__ = ["MIN_STEPS_PER_MESH_PERIOD", "check_time_step", "mesh_events_per_input_turn"]

MIN_STEPS_PER_MESH_PERIOD = 10
"""Fewest time steps per period of the fastest mesh at the scene's highest stated speed.
At 10 the average-acceleration rule lengthens the mesh period by (2 pi / 10)^2 / 12 =
3.3 %, and the pair curve is sampled at 10 points of each cycle; below 2 the mesh
frequency aliases.  The shipped cases run 43 (NREL 5 MW emergency stop) to 864 steps
per period."""

_DEFAULT_INPUT = {"planetary": "carrier", "parallel": "input_gear", "inertia": "body"}


def mesh_events_per_input_turn(gearbox: object) -> dict[str, float]:
    """Tooth engagements per turn of the gearbox's input member, by stage name.

    Returns an empty dict when the gearbox's input is not its first stage's input
    member (the series-chain rule above does not apply) or no stage has tooth numbers.
    """
    stages = gearbox.stages
    if not stages:
        return {}
    first = stages[0]
    if gearbox.input != f"{first.name}.{_DEFAULT_INPUT.get(first.kind, '')}.theta_z":
        return {}
    ratio = 1.0  # speed of the stage's input member over the gearbox input's
    events = {}
    for stage in stages:
        if stage.kind == "planetary":
            if stage.ring.teeth:
                events[stage.name] = stage.ring.teeth * ratio
            ratio *= stage.speed_ratio
        elif stage.kind == "parallel":
            if stage.input_gear.teeth:
                events[stage.name] = stage.input_gear.teeth * ratio
            ratio /= stage.speed_ratio
    return events


def check_time_step(gearbox: object, transient: object, path: str) -> None:
    """Raise :class:`CaseError` when ``transient.time_step`` is longer than
    1/:data:`MIN_STEPS_PER_MESH_PERIOD` of the fastest mesh period at the scene's
    highest stated input speed (``initial_speed_rpm``, ``speed_reference_rpm``).

    The message names the time step, the speed, the stage and its mesh frequency, and
    the longest step the rule allows.
    """
    speeds = [abs(transient.initial_speed_rpm), transient.speed_reference_rpm or 0.0]
    speed = max(speeds)
    events = mesh_events_per_input_turn(gearbox)
    if speed <= 0 or not events:
        return
    stage, per_turn = max(events.items(), key=lambda item: item[1])
    frequency = per_turn * speed / 60.0
    steps = 1.0 / (frequency * transient.time_step)
    if steps < MIN_STEPS_PER_MESH_PERIOD:
        which = "initial_speed_rpm" if speed == speeds[0] else "speed_reference_rpm"
        longest = 1.0 / (MIN_STEPS_PER_MESH_PERIOD * frequency)
        raise CaseError(
            f"{path}.time_step = {transient.time_step!r} s does not resolve the meshes: at "
            f"{which} = {speed:g} rpm stage {stage} meshes at {frequency:.4g} Hz, "
            f"{steps:.3g} steps per mesh period; at least {MIN_STEPS_PER_MESH_PERIOD} are "
            f"needed (time_step <= {longest:.3g} s, or a lower speed)"
        )
