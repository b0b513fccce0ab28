"""Sphinx extension: the reference of every case parameter, written at build time.

Each dataclass a case file builds (:data:`GROUPS`) gets a table with one row per field:
its name, type, unit, default, and the description that states its rule.  Name,
default and inheritance come from :func:`dataclasses.fields`; type, unit and
description from the class's numpydoc "Parameters" section, read with numpydoc's own
parser.  The unit is the bracketed part of the description (``Stiffness in z [N/m]``;
``[-]`` for a pure number).

The build fails (a Sphinx warning, and the site is built with ``-W``) when

- a field has no entry in its class's Parameters section (or one of its bases'),
- a Parameters entry names no field,
- a field that holds a real number gives no unit,
- a dataclass of :mod:`pygear.model` is neither in :data:`GROUPS` nor in
  :data:`INTERNAL` (a new component would otherwise go unlisted).

The page is written to ``generated/parameters.rst`` (not kept in git).
"""

from __future__ import annotations

import dataclasses
import importlib
import math
import pkgutil
import re
from dataclasses import dataclass
from pathlib import Path

from numpydoc.docscrape import NumpyDocString
from sphinx.application import Sphinx
from sphinx.util import logging

logger = logging.getLogger(__name__)

GROUPS: tuple[tuple[str, str, tuple[str, ...]], ...] = (
    (
        "Case and scenes",
        "A case file's ``case = Case(...)``, the scenes it runs and the settings of a "
        "scene's ``response`` analysis.",
        (
            "model.case.Case",
            "model.case.Scene",
            "model.case.RayleighDamping",
            "model.response_settings.Response",
        ),
    ),
    (
        "Transient settings",
        "The ``transient`` of a scene: time stepping, torque laws, output probes and the "
        "reductions counted on the fly.",
        (
            "model.transient_settings.Transient",
            "model.transient_settings.TorqueLaw",
            "model.transient_settings.Probe",
            "model.reduction_settings.Reductions",
        ),
    ),
    (
        "Gearbox and stages",
        "Stages on one housing and the couplings between them.",
        (
            "model.gearbox.Gearbox",
            "model.planetary.PlanetaryStage",
            "model.gearbox.ParallelStage",
            "model.gearbox.ShaftInertia",
            "model.gearbox.RigidLink",
            "model.gearbox.TorsionalSpring",
        ),
    ),
    (
        "Bodies and gears",
        "Rigid bodies: their inertia, and for gears their radii or their involute geometry.",
        (
            "model.bodies.Body",
            "model.bodies.Gear",
            "model.bodies.Carrier",
            "model.gear_geometry.GearGeometry",
            "model.gear_geometry.MeshGeometry",
        ),
    ),
    (
        "Bearings and meshes",
        "The springs between members: bearings to the housing or the carrier, and meshes.",
        (
            "model.bearings.Bearing",
            "model.bearings.PlanetBearing",
            "model.meshes.Mesh",
        ),
    ),
    (
        "Tooth defects and faults",
        "Weakened or damaged teeth, in a case or a scene.",
        (
            "model.defects.ToothDefect",
            "model.tooth_faults.RootCrack",
            "model.tooth_faults.Spall",
            "model.tooth_faults.ChippedTooth",
        ),
    ),
    (
        "Flank micro-geometry",
        "A gear's modifications, deviations and misalignment for the loaded tooth contact "
        "analysis (``Gear(modifications=...)``, ``pygear contact``).",
        (
            "model.micro_geometry.Modifications",
            "model.micro_geometry.ProfileRelief",
            "model.micro_geometry.EndRelief",
            "model.micro_geometry.Deviations",
            "model.micro_geometry.Misalignment",
        ),
    ),
    (
        "Rolling bearings",
        "Rolling-element bearings as case data: their geometry for the defect frequencies "
        "and contact loads, and their defects.",
        (
            "model.rolling_bearing.RollingBearing",
            "model.rolling_bearing.BearingDefect",
            "model.rolling_bearing.DistributedFault",
        ),
    ),
    (
        "Sensors",
        "Accelerometers on the ring or housing of a planetary stage.",
        ("model.sensors.Sensor", "model.sensors.StructuralMode"),
    ),
    (
        "Drivetrain",
        "Flexible shafts, their bearings and couplings, the rotor and the generator around "
        "the gearbox (``Case.drivetrain``).",
        (
            "model.drivetrain.Drivetrain",
            "model.drivetrain.Shaft",
            "model.drivetrain.ShaftSection",
            "model.drivetrain.ShaftBearing",
            "model.drivetrain.Coupling",
            "model.drivetrain.Rotor",
            "model.drivetrain.Generator",
            "model.drivetrain.GearboxMount",
            "model.rotor.Disc",
            "model.rotor.BearingCoefficients",
            "model.rotor_case.RotorCase",
            "model.rotor_transient.RotorScene",
            "model.rotor_transient.RotorRun",
            "model.rotor_transient.DiscUnbalance",
        ),
    ),
    (
        "Rating",
        "A case file's module-level ``rating = Rating(...)``, read by ``pygear rate`` "
        "(:doc:`/rating`): materials, rated load, required safeties, duty cycle and "
        "bearings.",
        (
            "model.rating.Rating",
            "model.rating.Material",
            "model.rating.DutyCycle",
            "model.rating.RollingBearingData",
        ),
    ),
    (
        "Design load cases",
        "A case file's module-level ``design_load_cases = DesignLoadCases(...)``, run by "
        "``pygear batch CASE --dlc`` (:doc:`/long_runs`): wind speeds, seeds, duration "
        "and the torque source.",
        ("model.dlc_settings.DesignLoadCases",),
    ),
)
"""Sections of the page and the dataclasses (below ``pygear.``) each documents."""

INTERNAL = {
    "model.scene_settings.SceneSettings": "what assembly reads of a scene, built from it",
    "model.gear_geometry.MeshModelInputs": "quantities derived from gear geometry",
    "model.plausibility.PlausibleRange": "a row of the plausible-range table, not an input",
    "model.dlc_settings.LoadCase": "one row a design load case table expands to",
}
"""Dataclasses of :mod:`pygear.model` that a case file never writes, and why."""

UNIT = re.compile(r"\[([^\[\]]+)\]")
INTERVAL = re.compile(r"^[\s\d.eE+\-,]*\d[\s\d.eE+\-,]*$")
"""A bracket holding only numbers is an interval (``in [0, 1]``), not a unit."""

SKIPPED_FIELDS = ("_derived",)
"""Fields a case never writes: the record of values derived from gear geometry."""


@dataclass(frozen=True)
class Row:
    """One field of a dataclass, as the page shows it."""

    name: str
    type: str
    unit: str
    default: str
    description: str


def _class(path: str) -> type:
    module, name = path.rsplit(".", 1)
    return getattr(importlib.import_module(f"pygear.{module}"), name)


def _parameters(cls: type) -> dict[str, tuple[str, list[str], str]]:
    """``{field name: (type, description lines, unit)}`` from the class's and its bases'
    Parameters sections; an entry ``a, b : float`` documents both names."""
    documented: dict[str, tuple[str, list[str], str]] = {}
    for klass in reversed(cls.__mro__):
        if klass is object or not klass.__doc__:
            continue
        for parameter in NumpyDocString(klass.__doc__)["Parameters"]:
            names = [n.strip() for n in parameter.name.split(",")]
            units = _units(parameter.desc, len(names))
            for name, unit in zip(names, units):
                documented[name] = (parameter.type, parameter.desc, unit)
    return documented


def _units(description: list[str], count: int) -> list[str]:
    """The unit of each of ``count`` names an entry documents: one bracket for all, one
    bracket per name, or one bracket listing a unit per name (``[Pa, -]``)."""
    found = [u.strip() for u in UNIT.findall(" ".join(description)) if not INTERVAL.match(u)]
    if not found:
        return [""] * count
    if len(found) == count:
        return found
    parts = [p.strip() for p in found[0].split(",")]
    if count > 1 and len(parts) == count:
        return parts
    return [found[0]] * count


def _default(spec: dataclasses.Field) -> str:
    if spec.default is not dataclasses.MISSING:
        value = spec.default
    elif spec.default_factory is not dataclasses.MISSING:
        value = spec.default_factory()
    else:
        return "required"
    if isinstance(value, float) and math.isnan(value):
        return "from geometry"
    if dataclasses.is_dataclass(value):
        return f"``{type(value).__name__}()``"
    return f"``{value!r}``"


def _needs_unit(type_text: str) -> bool:
    return "float" in type_text


DOCS_PAGE = re.compile(r"docs/([a-z_]+)\.md")


LITERAL = re.compile(r"(``.+?``|`[^`]*`)")
"""Literal text and interpreted text (roles) inside a description."""


def _escape_bars(text: str) -> str:
    """Absolute values written ``|x|`` read as reStructuredText substitutions: escape
    every bar outside literal and interpreted text (as conf.py does for docstrings)."""
    parts = LITERAL.split(text)
    return "".join(p if k % 2 else p.replace("|", r"\|") for k, p in enumerate(parts))


def _rst(lines: list[str]) -> str:
    """Description lines as one paragraph, bars escaped, docs pages cited by path made
    links."""
    text = _escape_bars(" ".join(line.strip() for line in lines))
    return DOCS_PAGE.sub(lambda m: f":doc:`docs/{m.group(1)}.md </{m.group(1)}>`", text)


def rows(cls: type, problems: list[str]) -> list[Row]:
    """The table rows of ``cls``; what is missing is appended to ``problems``."""
    documented = _parameters(cls)
    result = []
    names = []
    for spec in dataclasses.fields(cls):
        if not spec.init or spec.name in SKIPPED_FIELDS:
            continue
        names.append(spec.name)
        entry = documented.get(spec.name)
        if entry is None or not " ".join(entry[1]).strip():
            problems.append(f"{cls.__name__}.{spec.name}: no description in Parameters")
            continue
        type_text, description, unit = entry
        type_text = type_text or str(spec.type)
        if not unit and _needs_unit(type_text):
            problems.append(
                f"{cls.__name__}.{spec.name}: a real number without a unit "
                "(write it in brackets, [-] for a pure number)"
            )
        result.append(Row(spec.name, type_text, unit, _default(spec), _rst(description)))
    own = {
        n.strip()
        for p in NumpyDocString(cls.__doc__ or "")["Parameters"]
        for n in p.name.split(",")
    }
    for name in sorted(own - set(names)):
        problems.append(f"{cls.__name__}: Parameters documents {name!r}, which is no field")
    return result


def model_dataclasses() -> set[str]:
    """Every dataclass defined in a module of :mod:`pygear.model`, as ``model.mod.Name``."""
    import pygear.model

    found = set()
    for info in pkgutil.iter_modules(pygear.model.__path__):
        module = importlib.import_module(f"pygear.model.{info.name}")
        for name, value in vars(module).items():
            if (
                isinstance(value, type)
                and dataclasses.is_dataclass(value)
                and value.__module__ == module.__name__
            ):
                found.add(f"model.{info.name}.{name}")
    return found


def _summary(cls: type) -> str:
    doc = NumpyDocString(cls.__doc__ or "")
    return _escape_bars(
        " ".join(line.strip() for line in doc["Summary"] + [""] + doc["Extended Summary"])
    )


def _table(table_rows: list[Row]) -> list[str]:
    lines = [
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 16 14 8 12 50",
        "   :class: parameter-table",
        "",
        "   * - field",
        "     - type",
        "     - unit",
        "     - default",
        "     - meaning and rule",
    ]
    for row in table_rows:
        lines += [
            f"   * - ``{row.name}``",
            f"     - {row.type}",
            f"     - {row.unit or '—'}",
            f"     - {row.default}",
            f"     - {row.description}",
        ]
    return lines


def page(problems: list[str]) -> str:
    """The whole page as reStructuredText."""
    listed = {path for _, _, paths in GROUPS for path in paths}
    for path in sorted(model_dataclasses() - listed - set(INTERNAL)):
        problems.append(f"pygear.{path}: a dataclass of pygear.model missing from the reference")
    title = "Case parameters"
    lines = [
        ".. This page is written by docs/_ext/parameter_reference.py on every build.",
        "",
        title,
        "=" * len(title),
        "",
        "Every field of every object a case file builds, generated from the dataclasses of",
        ":mod:`pygear.model` and their docstrings. Values are SI (m, kg, s, N, rad) unless",
        "the unit column says otherwise; angles are in degrees only in fields ending in",
        "``_deg``. *required* marks a field without a default; *from geometry* a value",
        "that gear geometry derives when it is left out (typed, it must agree). A case is",
        "checked as a whole before any work, and the first value that breaks its rule is",
        "named by its path (``planetary.sun_mesh.stiffness``); see :doc:`/writing_a_case`.",
        "Beyond the rules below, every real number must be finite, and positive SI",
        "magnitudes lie between 1e-15 and 1e15.",
        "",
    ]
    for heading, intro, paths in GROUPS:
        lines += [heading, "-" * len(heading), "", intro, ""]
        for path in paths:
            cls = _class(path)
            name = f"{cls.__name__}"
            bases = [b.__name__ for b in cls.__mro__[1:-1] if dataclasses.is_dataclass(b)]
            lines += [
                f".. _param-{cls.__name__.lower()}:",
                "",
                name,
                "~" * len(name),
                "",
                f"``{cls.__module__}.{cls.__name__}``"
                + (f" (fields of {', '.join(bases)} included)" if bases else ""),
                "",
                _summary(cls),
                "",
            ]
            lines += _table(rows(cls, problems))
            lines.append("")
    return "\n".join(lines) + "\n"


def write_page(app: Sphinx) -> None:
    """Write ``generated/parameters.rst``; report each missing piece as a warning."""
    problems: list[str] = []
    text = page(problems)
    target = Path(app.srcdir) / "generated" / "parameters.rst"
    target.parent.mkdir(exist_ok=True)
    if not target.is_file() or target.read_text() != text:
        target.write_text(text)
    for problem in problems:
        logger.warning("parameter reference: %s", problem, location="generated/parameters")


def setup(app: Sphinx) -> dict:
    app.connect("builder-inited", write_page)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
