"""``pygear contact CASE --mesh MESH [--torque T | --torques A:B:N] [--json] [--out DIR]``:
the loaded tooth contact of one mesh.

Runs the loaded tooth contact analysis (the documentation's contact page) of MESH over
a mesh cycle at each torque (the torque this mesh carries on its first-named gear: the
sun, the ring, the input gear) and prints the TE, its harmonics, K_Hbeta, K_Halpha and the Hertzian
pressure per torque; ``--json`` prints one JSON object instead; ``--out`` writes
``contact.nc``, ``contact.md`` and ``contact.png`` (TE curves, the TE peak-to-peak
against torque and the contact pattern).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

__all__ = ["HANDLERS", "add_parsers"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``contact`` subcommand."""
    contact = commands.add_parser(
        "contact",
        help="loaded tooth contact analysis of one mesh: TE, contact pattern, K_Hbeta",
        description="Loaded tooth contact analysis of one mesh of CASE over a mesh cycle: "
        "transmission error and its harmonics, the contact pattern, K_Hbeta, K_Halpha and "
        "the Hertzian pressure, with the gears' modifications, deviations and misalignment.",
    )
    contact.add_argument("case", metavar="CASE", help="case directory or case name")
    contact.add_argument("--mesh", required=True, help="mesh name (an error lists them)")
    contact.add_argument("--scene", help="apply this scene's parameter changes first")
    contact.add_argument(
        "--torque", type=float, metavar="T", help="torque of this mesh on its first gear [N m]"
    )
    contact.add_argument(
        "--torques", metavar="A:B:N", help="N torques from A to B [N m] (the Harris map)"
    )
    contact.add_argument("--slices", type=int, default=40, help="slices along the face")
    contact.add_argument(
        "--positions", type=int, default=20, help="positions per mesh cycle"
    )
    contact.add_argument(
        "--cycles", type=int, default=1,
        help="mesh cycles to cover (pitch deviations and runout: a revolution)",
    )  # fmt: skip
    contact.add_argument(
        "--coupling-length", type=float, default=0.0, metavar="M",
        help="decay length of the slices' Pasternak coupling [m]; 0 (default) uncoupled",
    )  # fmt: skip
    contact.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    contact.add_argument(
        "--out", type=Path, help="write contact.nc, contact.md and contact.png here"
    )


def _contact(args: argparse.Namespace) -> int:
    from ..analysis.contact.ltca_case import case_loaded_contact
    from ..errors import CaseError
    from ..model.case import load_case
    from ..runs.contact_outputs import contact_json, parse_torques, write_contact_outputs
    from ..runs.json_output import json_text

    for option, value, low, high in (("--slices", args.slices, 1, 400),
                                     ("--positions", args.positions, 2, 2000),
                                     ("--cycles", args.cycles, 1, 10_000)):  # fmt: skip
        if not low <= value <= high:
            raise CaseError(f"{option} must be a whole number in [{low}, {high}] (got {value})")
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "contact")
    torques = parse_torques(args.torque, args.torques)
    case = load_case(args.case)
    if args.scene is not None:
        case = case.for_scene(case.scene(args.scene))
    ds = case_loaded_contact(case, args.mesh, torques, n_slice=args.slices,
                             n_position=args.positions, cycles=args.cycles,
                             coupling_length=args.coupling_length)  # fmt: skip
    if args.out is not None:
        from ..plots.contact import plot_contact

        write_contact_outputs(ds, args.out)
        plot_contact(ds, args.out / "contact.png")
    if args.json:
        print(json_text(contact_json(ds)))
        return 0
    print(f"{ds.attrs['case']} {ds.attrs['mesh']}: eps_alpha {ds.attrs['eps_alpha']:.4g}, "
          f"eps_beta {ds.attrs['eps_beta']:.4g}; {ds.attrs.get('source', '')}")
    print(f"{'torque N m':>12}{'force N':>12}{'mean TE um':>12}{'TE p-p um':>11}"
          f"{'TE 1x um':>10}{'TE 2x um':>10}{'K_Hbeta':>9}{'K_Halpha':>10}{'p_H MPa':>10}")
    second = ds.te_harmonics.sizes["order"] > 1
    for i in range(ds.force.size):
        two = float(ds.te_harmonics[i, 1]) * 1e6 if second else float("nan")
        print(f"{float(ds.torque[i]):12.5g}{float(ds.force[i]):12.5g}"
              f"{float(ds.mean_te[i]) * 1e6:12.4g}{float(ds.te_peak_to_peak[i]) * 1e6:11.4g}"
              f"{float(ds.te_harmonics[i, 0]) * 1e6:10.4g}{two:10.4g}"
              f"{float(ds.k_h_beta[i]):9.4g}{float(ds.k_h_alpha[i]):10.4g}"
              f"{float(ds.max_contact_pressure[i]) / 1e6:10.4g}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"contact": _contact}
