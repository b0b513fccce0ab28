"""Every figure kind of pygear.plots drawn from real small results of the study case
(yang2016_planetary, its scenes shortened with ``dataclasses.replace``) and of the
gearbox (yang2016_gearbox).

Each figure is checked for what a report needs: it is returned as a Figure, every axis
carries a label with units in brackets (on itself or on an axes it shares that axis
with), the titles name the case, the scene and the formulation, no two texts drawn on
the canvas overlap and none leaves the figure, and it saves as a PNG.  Figure by
figure: the speed plot spans the whole run (longer than the 2 s the seed's figure
shows), two runs of one formulation get titles that tell them apart, the gearbox's
panels name their stage, peak labels point at peaks of the tables, and a helical
stage's mode is drawn in the axial planes where its gears move along the axis, while
the same mode of a spur pair has no out-of-plane motion to draw.
"""

from __future__ import annotations

import dataclasses
import re
from itertools import combinations

import matplotlib.text as mtext
import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.text import Annotation, Text

from pygear import load_case
from pygear.analysis.contact.mesh_stiffness import mesh_stiffness_at_constant_speed
from pygear.analysis.modes.campbell import campbell_diagram
from pygear.analysis.modes.modal import modal_analysis
from pygear.analysis.modes.sensitivity import frequency_sweep
from pygear.analysis.signals.analyze import analyze_channel
from pygear.analysis.signals.order_plan import plan_order_tracking
from pygear.analysis.signals.order_tracking import track_orders
from pygear.analysis.time.accuracy import AccuracyStudy
from pygear.analysis.time.transient import run_transient
from pygear.assembly.matrices import assemble
from pygear.io import save_figure
from pygear.plots.accuracy import plot_pareto
from pygear.plots.campbell import plot_campbell
from pygear.plots.mesh import plot_mesh_stiffness
from pygear.plots.modal import plot_frequency_sweep, plot_modal_energy, plot_mode_shape
from pygear.plots.mode_shape import stage_mode
from pygear.plots.orders import plot_order_map, plot_order_slices, plot_order_spectrum
from pygear.plots.signal import plot_run_analysis
from pygear.plots.transient import plot_speeds
from pygear.runs.outputs import analysis_references, stored_references

UNITS = re.compile(r"\[[^\[\]]+\]")
"""Units in brackets, e.g. ``[rpm]``, ``[-]``, ``[$10^8$ N/m]``."""

STUDY = "yang2016_planetary"
GEARBOX = "yang2016_gearbox"
LONG_RUN_S = 2.5
"""Duration of the study run-up drawn [s]: past the 2 s the seed's Figure 9 shows."""


# --------------------------------------------------------------------------- results


def _shortened(case, scene_name: str, **transient):
    scene = case.scene(scene_name)
    return dataclasses.replace(scene, transient=dataclasses.replace(scene.transient, **transient))


def _run(case, scene):
    run = run_transient(case, scene)
    return run.merge(analysis_references(case, assemble(case, scene), run))


@pytest.fixture(scope="module")
def study():
    return load_case(STUDY)


@pytest.fixture(scope="module")
def gearbox():
    return load_case(GEARBOX)


@pytest.fixture(scope="module")
def study_runs(study):
    """The run-up over 2.5 s and the planet-error run-up over 0.5 s: one formulation."""
    return [
        _run(study, _shortened(study, "runup", duration=LONG_RUN_S, mean_window=0.5)),
        _run(study, _shortened(study, "runup_planet_error", duration=0.5, mean_window=0.1)),
    ]


@pytest.fixture(scope="module")
def gearbox_run(gearbox):
    return _run(gearbox, _shortened(gearbox, "runup_tv", duration=0.3, mean_window=0.1))


def _modal(case, scene_name: str = "modal"):
    model = assemble(case, case.scene(scene_name))
    return model, modal_analysis(model).assign_attrs(scene=scene_name)


# --------------------------------------------------------------------------- checks


@pytest.fixture
def drawn(monkeypatch) -> list[Text]:
    """The visible texts each ``canvas.draw()`` draws (tick labels out of view, clipped
    annotations and hidden texts are not drawn, so they are not listed)."""
    texts: list[Text] = []
    draw = mtext.Text.draw

    def recording(self, renderer):
        if self.get_visible() and self.get_text().strip():
            texts.append(self)
        return draw(self, renderer)

    monkeypatch.setattr(mtext.Text, "draw", recording)
    return texts


def _titles(figure: Figure) -> list[str]:
    titles = [figure.get_suptitle()]
    for ax in figure.axes:
        if ax.get_visible():
            titles += [ax.get_title(loc=loc) for loc in ("left", "center", "right")]
    return [title for title in titles if title]


def _has_units(ax, which: str) -> bool:
    """Whether the x or y axis of ``ax`` has a label with units, or shares its axis
    with a visible axes whose label has them."""
    label = {"x": lambda a: a.get_xlabel(), "y": lambda a: a.get_ylabel()}[which]
    shared = (ax.get_shared_x_axes() if which == "x" else ax.get_shared_y_axes()).get_siblings(ax)
    return any(UNITS.search(label(other)) for other in shared if other.get_visible())


def _check(
    figure, drawn: list[Text], tmp_path, name: str, *, case: str, scenes, formulations
) -> None:
    """What every figure must satisfy (module docstring)."""
    assert isinstance(figure, Figure)
    for ax in figure.axes:
        if not ax.get_visible():
            continue
        if ax.get_label() == "<colorbar>":  # a colour bar labels its long axis only
            assert UNITS.search(ax.get_ylabel() or ax.get_xlabel()), name
            continue
        assert _has_units(ax, "x"), f"{name}: x axis {ax.get_xlabel()!r} has no units"
        assert _has_units(ax, "y"), f"{name}: y axis {ax.get_ylabel()!r} has no units"
    titles = "\n".join(_titles(figure))
    assert case in titles, f"{name}: titles do not name the case {case!r}: {titles!r}"
    for scene in scenes:
        assert scene in titles, f"{name}: titles do not name {scene!r}: {titles!r}"
    for formulation in formulations:
        assert f"{formulation} formulation" in titles, f"{name}: {titles!r}"

    drawn.clear()
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    # an annotation's own extent includes its leader line: compare the text alone
    boxes = [(text, Text.get_window_extent(text, renderer)) for text in dict.fromkeys(drawn)]
    assert boxes, name
    for (first, a), (second, b) in combinations(boxes, 2):
        assert not a.overlaps(b), (
            f"{name}: {first.get_text()!r} overlaps {second.get_text()!r} ({a} and {b})"
        )
    frame = figure.bbox
    for text, box in boxes:
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1, (name, text.get_text(), box)
        assert frame.y0 <= box.y0 and box.y1 <= frame.y1, (name, text.get_text(), box)

    path = save_figure(figure, tmp_path / f"{name}.png", dpi=figure.dpi)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# --------------------------------------------------------------------------- transient


def test_speeds_cover_the_whole_run_and_tell_the_runs_apart(study_runs, drawn, tmp_path):
    figure = plot_speeds(study_runs)
    _check(
        figure,
        drawn,
        tmp_path,
        "speeds",
        case=STUDY,
        scenes=("scene runup,", "scene runup_planet_error,"),
        formulations=("improved",),
    )
    columns = [ax.get_title() for ax in figure.axes if ax.get_title()]
    assert len(columns) == 2 and columns[0] != columns[1]
    end = float(study_runs[0].time[-1])
    assert end == pytest.approx(LONG_RUN_S)
    panels = [ax for ax in figure.axes if ax.get_visible()]
    assert len(panels) == 6  # carrier, sun and planet 1 speeds of two runs
    for ax in panels:
        low, high = ax.get_xlim()
        assert low <= 0.0 and high >= end, ax.get_xlim()
    # the long run's envelope reaches the end but for its last pixel column's half
    first_column = panels[0::2]
    for ax in first_column:
        (band,) = ax.collections
        drawn_end = max(path.vertices[:, 0].max() for path in band.get_paths())
        column_s = (high - low) / ax.get_window_extent().width
        assert drawn_end >= end - column_s, (drawn_end, end)


def test_gearbox_speed_rows_name_their_stage(gearbox, gearbox_run, drawn, tmp_path):
    figure = plot_speeds([gearbox_run])
    _check(
        figure,
        drawn,
        tmp_path,
        "gearbox_speeds",
        case=GEARBOX,
        scenes=("scene runup_tv",),
        formulations=("improved",),
    )
    stages = tuple(f"{stage.name}." for stage in gearbox.gearbox.stages)
    labels = [ax.get_ylabel() for ax in figure.axes]
    assert len(labels) == 8  # the scene's eight speed probes
    assert all(label.startswith(stages) for label in labels), labels


def test_signal_analysis_labels_its_peaks(study_runs, drawn, tmp_path):
    run = study_runs[0]
    natural, mesh = stored_references(run)
    analysis = analyze_channel(run, after=1.0, natural_frequencies=natural, mesh_frequency=mesh)
    figure = plot_run_analysis(analysis, run_attrs=run.attrs)
    _check(
        figure,
        drawn,
        tmp_path,
        "signal",
        case=STUDY,
        scenes=("scene runup",),
        formulations=("improved",),
    )
    tables = ("spectrum", "spectrum", "dra_spectrum", "envelope_spectrum")
    for ax, table in zip(figure.axes[1:], tables, strict=True):
        labels = [text for text in ax.texts if isinstance(text, Annotation)]
        assert labels, ax.get_title()
        peaks = analysis.peaks[table].frequency_hz.values
        for label in labels:  # each points at a peak of its table, and stays above the data
            assert np.min(np.abs(peaks - label.xy[0])) == 0.0, label.get_text()
            assert label.xy[1] < ax.get_ylim()[1]


# --------------------------------------------------------------------------- modal


@pytest.mark.parametrize("name", [STUDY, GEARBOX])
def test_modal_energy_panels_name_their_stage(name, drawn, tmp_path):
    case = load_case(name)
    _, modal = _modal(case)
    figure = plot_modal_energy(modal)
    _check(
        figure,
        drawn,
        tmp_path,
        f"energy_{name}",
        case=name,
        scenes=("scene modal",),
        formulations=("improved",),
    )
    stages = tuple(f"{stage.name}: " for stage in case.gearbox.stages)
    panels = [ax for ax in figure.axes if ax.get_visible()]
    assert all(ax.get_title().startswith(stages) for ax in panels)
    # one panel per distinct non-zero frequency
    frequency = modal.frequency.values
    distinct = np.unique(np.round(frequency[frequency > 0], 6))
    assert len(panels) == len(distinct)


def test_planetary_mode_shape(study, drawn, tmp_path):
    model, modal = _modal(study)
    mode = int(
        np.flatnonzero((modal.mode_class.values == "rotational") & (modal.class_index.values == 2))[
            0
        ]
    )
    figure = plot_mode_shape(study, model, modal, mode)
    _check(
        figure,
        drawn,
        tmp_path,
        "mode_shape",
        case=STUDY,
        scenes=("scene modal",),
        formulations=("improved",),
    )
    assert len(figure.axes) == 1  # a spur stage moves in its plane only
    # Yang, Jiang & Han (2016) Table 2: 1334.0 Hz; the title rounds to 0.1 Hz, far above
    # the eigensolver's round-off
    assert "of planetary: rotational 2, 1334.0 Hz" in figure.get_suptitle()


def _axial_segments(ax) -> list[np.ndarray]:
    """The solid segments of an axial-plane panel (the moved gears), as (z, across) pairs."""
    return [
        np.asarray(line.get_xydata())
        for line in ax.lines
        if line.get_linestyle() == "-" and len(line.get_xydata()) == 2
    ]


def test_helical_stage_mode_moves_out_of_plane(gearbox, drawn, tmp_path):
    model, modal = _modal(gearbox)
    mode = stage_mode(modal, "parallel")
    assert mode is not None and modal.mode_class.values[mode] == "rotational"
    figure = plot_mode_shape(gearbox, model, modal, mode, stage="parallel")
    _check(
        figure,
        drawn,
        tmp_path,
        "mode_shape_parallel",
        case=GEARBOX,
        scenes=("scene modal",),
        formulations=("improved",),
    )
    front, side, top = figure.axes
    assert [ax.get_xlabel() for ax in (side, top)] == ["z [m]", "z [m]"]
    # a helical mesh force has an axial part: the gears move along the axis, in
    # opposite senses (the axial forces on the two flanks are equal and opposite)
    z_rest = gearbox.gearbox.stages[2].axial_position
    for ax in (side, top):
        segments = _axial_segments(ax)
        assert len(segments) == 2
        centres = [segment[:, 0].mean() - z_rest for segment in segments]
        # drawn offsets are EDGE_SHARE of a half-width of about 0.1 m: millimetres,
        # far above the 1e-12 m round-off of the drawing's arithmetic
        assert min(abs(c) for c in centres) > 1e-4, centres
        assert centres[0] * centres[1] < 0, centres


def test_spur_pair_mode_has_nothing_out_of_plane(gearbox):
    """The same gearbox with a spur parallel pair: its model keeps no out-of-plane DOF
    of the pair (pygear's per-stage DOF set), so the mode is drawn in its plane only."""
    stages = list(gearbox.gearbox.stages)
    stages[2] = dataclasses.replace(stages[2], base_helix_angle_deg=0.0, overlap_ratio=0.0)
    spur = dataclasses.replace(
        gearbox, gearbox=dataclasses.replace(gearbox.gearbox, stages=tuple(stages))
    )
    model, modal = _modal(spur)
    figure = plot_mode_shape(spur, model, modal, stage_mode(modal, "parallel"), stage="parallel")
    assert len(figure.axes) == 1


def test_frequency_sweep(study, drawn, tmp_path):
    sweep = frequency_sweep(
        study,
        "planetary.sun_mesh.stiffness",
        np.geomspace(1e7, 1e10, 6),
        formulations=("improved", "lin-parker"),
    )
    figure = plot_frequency_sweep(sweep)
    _check(
        figure,
        drawn,
        tmp_path,
        "sweep",
        case=STUDY,
        scenes=("no scene",),
        formulations=("improved", "lin-parker"),
    )


def test_campbell(study, drawn, tmp_path):
    campbell = campbell_diagram(study, np.linspace(0.0, 3000.0, 13), scene=study.scene("modal"))
    figure = plot_campbell(campbell)
    _check(
        figure,
        drawn,
        tmp_path,
        "campbell",
        case=STUDY,
        scenes=("scene modal",),
        formulations=("improved",),
    )
    names = {text.get_text() for text in figure.axes[0].texts}
    # the sun and ring mesh lines nearly coincide (orders 95.9 and 96): both named
    assert {"planetary sun mesh 1x", "planetary ring mesh 1x"} <= names


# --------------------------------------------------------------------------- others


@pytest.mark.parametrize("name", [STUDY, GEARBOX])
def test_mesh_stiffness_panels_name_their_stage(name, drawn, tmp_path):
    case = load_case(name)
    figure = plot_mesh_stiffness(mesh_stiffness_at_constant_speed(case))
    _check(
        figure,
        drawn,
        tmp_path,
        f"mesh_{name}",
        case=name,
        scenes=("no scene",),
        formulations=("improved",),
    )
    first = case.gearbox.stages[0].name
    assert all(f") {first}." in ax.get_title(loc="left") for ax in figure.axes)


def test_order_tracking_figures(study, drawn, tmp_path):
    scene = _shortened(study, "runup_wide", duration=1.5, mean_window=0.1)
    run = _run(study, scene)
    result = track_orders(
        run, plan_order_tracking(run, "planetary.carrier", window_revolutions=0.25)
    )
    for plot in (plot_order_map, plot_order_spectrum, plot_order_slices):
        _check(
            plot(result, run_attrs=run.attrs),
            drawn,
            tmp_path,
            plot.__name__,
            case=STUDY,
            scenes=("scene runup_wide",),
            formulations=("improved",),
        )


def test_accuracy_pareto(study, drawn, tmp_path):
    from pygear.runs.accuracy import accuracy_study

    settings = AccuracyStudy(
        duration=0.3,
        mean_window=0.1,
        signal_after=0.1,
        coarsest_time_step=2.5e-5,
        levels=3,
        repeats=1,
        formulations=("improved",),
        dof_sets=("planar",),
        mesh_stiffness=("constant", "time-varying"),
        equivalent_loads=("predictor",),
    )
    study_result = accuracy_study(study, study.scene("runup"), settings)
    _check(
        plot_pareto(study_result, "improved"),
        drawn,
        tmp_path,
        "pareto",
        case=STUDY,
        scenes=("scene runup",),
        formulations=("improved",),
    )


@pytest.mark.parametrize("release", [False, True])
def test_save_figure_releases_only_when_asked(release, tmp_path):
    """A released figure is emptied once its file is written (its memory freed then, not
    at the next garbage collection); without ``release`` the caller keeps its figure."""
    figure = Figure(figsize=(2, 2), dpi=50)
    figure.add_subplot().plot([0, 1], [1, 0])
    path = save_figure(figure, tmp_path / "released.png", release=release)
    assert path.read_bytes().startswith(b"\x89PNG")
    assert len(figure.axes) == (0 if release else 1)
