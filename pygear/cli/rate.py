"""``pygear rate CASE [--scene S] [--duty-cycle FILE] [--json] [--out DIR]``: will it last?

Rates every mesh of the case to ISO 6336:2019 method B, the gears' damage and life
under the rating's duty cycle (or ``--duty-cycle``) to ISO 6336-6 and the bearings to
ISO 281, with the rating data the case file declares in ``rating = Rating(...)``.
Prints a table per gear and bearing and names the limiting element; ``--json`` prints
one JSON object instead; ``--out`` writes ``rating.nc``, ``rating.md`` and a figure.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

__all__ = ["HANDLERS", "add_parsers"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``rate`` subcommand."""
    rate = commands.add_parser(
        "rate",
        help="gear rating (ISO 6336), service life (ISO 6336-6) and bearing life (ISO 281)",
        description="Rate CASE's gears and bearings with the rating data its case file "
        "declares (`rating = Rating(...)`): safety factors, damage, lives, the limiting "
        "element.",
    )
    rate.add_argument("case", metavar="CASE", help="case directory or case name")
    rate.add_argument("--scene", help="apply this scene's parameter changes first")
    rate.add_argument(
        "--duty-cycle",
        type=Path,
        metavar="FILE",
        help="duty cycle instead of the case's: a CSV load spectrum (columns "
        "torque,hours[,speed_rpm]) or input torque series (time,torque); a pygear run file "
        "(its mesh forces, rainflow counted), a file of streamed reductions or a batch's "
        "combined spectrum (rainflow_mesh_force matrices or a load duration distribution, "
        "read as written); or an OpenFAST output (.out/.outb: rotor torque and speed)",
    )
    rate.add_argument(
        "--dynamic-factor",
        choices=("model", "iso"),
        default="model",
        help="K_v of meshes the case does not give: from the dynamic model's steady state "
        "at the rated speed (model, the default; ISO's method B where the model cannot "
        "give it, the output says why) or ISO 6336-1 method B (iso)",
    )
    rate.add_argument(
        "--face-load",
        choices=("iso", "model"),
        default=None,
        help="K_Hbeta of meshes the case does not give: ISO 6336-1 method C with no shaft "
        "mismatch (iso) or with the mismatch of the model's static deflection under the "
        "rated torque (model); default the case's Rating(face_load_from_model=...)",
    )
    rate.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    rate.add_argument("--out", type=Path, help="write rating.nc, rating.md and rating.png here")


def _rate(args: argparse.Namespace) -> int:
    import dataclasses

    from ..analysis.rating.dataset import rating_dataset
    from ..analysis.rating.gearbox_rating import model_dynamic_factors, rate_gearbox
    from ..model.rating import load_rating
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_out_dir
    from ..runs.rating_outputs import rating_json, write_rating_outputs

    check_out_dir("--out", args.out, "rate")
    case, rating = load_rating(args.case)
    if args.scene is not None:
        case = case.for_scene(case.scene(args.scene))
    notes: dict = {}
    record: dict = {}
    if args.duty_cycle is not None:
        duty, record, notes = _duty_file(args.duty_cycle, rating.rated_speed_rpm)
        if duty is not None:
            rating = dataclasses.replace(rating, duty_cycle=duty)
    if record:  # the record's meshes must be the case's, before the model's K_v
        from ..analysis.rating.gearbox_rating import check_record_meshes

        check_record_meshes(case, rating, record["matrices"])
    if args.face_load is not None:
        rating = dataclasses.replace(rating, face_load_from_model=args.face_load == "model")
    factors: dict = {}
    method = "ISO 6336-1:2019 method B (cl. 6.3), asked for with --dynamic-factor iso"
    if args.dynamic_factor == "model":
        factors, method = model_dynamic_factors(case, rating)
    result = rate_gearbox(case, rating, dynamic_factors=factors, dynamic_factor_method=method,
                          **record)
    ds = rating_dataset(result, rating, case.name)
    if args.out is not None:
        from ..plots.rating import plot_safety_factors

        write_rating_outputs(ds, rating, case.name, args.out, notes)
        plot_safety_factors(ds, args.out / "rating.png")
    if args.json:
        print(json_text(rating_json(ds)))
        return 0
    print(f"{'gear':<24}{'sigma_H MPa':>12}{'sigma_F MPa':>12}{'S_H':>8}{'S_F':>8}"
          f"{'damage':>10}{'life h':>11}")
    for gear in ds.gear.values:
        row = ds.sel(gear=gear)
        print(f"{gear:<24}{float(row.sigma_H):12.1f}{float(row.sigma_F):12.1f}"
              f"{float(row.S_H):8.3f}{float(row.S_F):8.3f}{float(row.damage):10.3g}"
              f"{float(row.life_h):11.3g}")
    if ds.sizes.get("bearing", 0):
        print(f"{'bearing':<24}{'P N':>12}{'L10 h':>12}{'L10m h':>12}")
        for bearing in ds.bearing.values:
            row = ds.sel(bearing=bearing)
            print(f"{bearing:<24}{float(row.bearing_P):12.4g}{float(row.bearing_L10_h):12.4g}"
                  f"{float(row.bearing_L10m_h):12.4g}")
    verdict = "passes" if ds.attrs["passed"] else "does NOT pass"
    print(f"limiting: {ds.attrs['limiting']} (margin {ds.attrs['limiting_margin']:.3f}); "
          f"the design {verdict} S_H >= {rating.required_sh:g}, S_F >= "
          f"{rating.required_sf:g} and {rating.service_life_h:g} h")
    return 0


def _duty_file(path: Path, rated_speed_rpm: float) -> tuple[object, dict, dict]:
    """(DutyCycle or None, rate_gearbox's record arguments, notes) of a --duty-cycle file:
    CSV, NetCDF (a run, its reductions, a batch's spectrum) or OpenFAST output."""
    from ..analysis.rating.duty_files import duty_from_dataset
    from ..errors import CaseError
    from ..runs.rating_outputs import read_duty_cycle

    suffix = path.suffix.lower()
    if suffix == ".csv":
        duty, notes = read_duty_cycle(path, rated_speed_rpm)
        return duty, {}, notes
    if not path.is_file():
        raise CaseError(f"--duty-cycle {str(path)!r}: no such file")
    if suffix in (".out", ".outb"):
        from ..io_openfast import read_openfast_output

        data = read_openfast_output(path)
    elif suffix in (".nc", ".nc4", ".netcdf"):
        from ..io import open_dataset

        try:
            data = open_dataset(path).load()
        except (OSError, ValueError) as error:
            raise CaseError(f"--duty-cycle {str(path)!r}: not a NetCDF file ({error})") from None
    else:
        raise CaseError(f"--duty-cycle {str(path)!r} must be a .csv, .nc, .out or .outb file")
    found = duty_from_dataset(data, str(path))
    record = {}
    if found.matrices:
        record = {"matrices": found.matrices, "record_s": found.record_s,
                  "record_speed_rpm": found.speed_rpm}
    return found.duty_cycle, record, found.notes


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"rate": _rate}
