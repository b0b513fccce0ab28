"""Duty cycles from files: a run's mesh forces against a hand Miner sum over the
``rainflow`` package's counts, a streamed run's reductions against its whole record, a
load duration distribution, an OpenFAST output, the K_v of the dynamic model, and the
one-line errors."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import rainflow
import xarray as xr

from pygear.analysis.rating import gearbox_rating
from pygear.analysis.rating.duty import cycles_to_failure
from pygear.analysis.rating.duty_files import duty_from_dataset
from pygear.analysis.rating.gear_rating import FactorValue, rate_pair
from pygear.analysis.rating.gearbox_rating import pair_loads, rate_gearbox
from pygear.cli.parser import main
from pygear.errors import CaseError
from pygear.model import gear_geometry as geo
from pygear.model.rating import load_rating

BINS = 64


@pytest.fixture(scope="module")
def nrel():
    return load_rating("nrel5mw_gearbox")


def _record(rating, seconds: float = 0.5, rate: float = 4000.0):
    """A synthetic run: stage 1's sun mesh of planet 1 at its rated force with a mesh
    ripple, a slow swell and a beat, and the input turning at the rated speed."""
    time = np.arange(0.0, seconds + 0.5 / rate, 1.0 / rate)
    t_sun = rating.rated_torque / (1.0 + 56.0 / 19.0) / 3.0
    nominal = t_sun / (19 * 0.045 / 2.0 * math.cos(math.radians(20.0)))  # along the LOA
    force = nominal * (1.0 + 0.08 * np.sin(2 * math.pi * 63.0 * time)
                       + 0.05 * np.sin(2 * math.pi * 3.1 * time)
                       + 0.03 * np.sin(2 * math.pi * 217.0 * time) ** 3)
    return xr.Dataset(
        {"mesh_force": (("mesh", "time"), force[None, :], {"units": "N"}),
         "speed": (("member", "time"), np.full((1, time.size), rating.rated_speed_rpm))},
        coords={"time": time, "mesh": ["stage1.sun-planet1"], "member": ["rotor.body"]},
        attrs={"input": "rotor.body.theta_z"},
    ), force, time


def _pow2_edges(values: np.ndarray) -> tuple[float, float]:
    """(width, lowest index) of power-of-two bins: the smallest width 2^e whose bins
    from floor(min / 2^e) to floor(max / 2^e) number at most BINS."""
    for e in range(-60, 80):
        w = 2.0**e
        low, high = math.floor(values.min() / w), math.floor(values.max() / w)
        if high - low + 1 <= BINS:
            return w, low
    raise AssertionError


def test_run_file_damage_is_the_hand_miner_sum_over_rainflow_counts(nrel):
    case, rating = nrel
    ds, force, time = _record(rating)
    found = duty_from_dataset(ds, "run.nc")
    result = rate_gearbox(case, rating, matrices=found.matrices, record_s=found.record_s,
                          record_speed_rpm=found.speed_rpm)
    # by hand: the package's cycles, each in its power-of-two bin, at the bin's peak
    # (upper mean edge + half the upper range edge); the record's tooth contacts shared
    # by count; each peak rated with K_A = K_gamma = K_v = 1; the sun's teeth meet three
    # planets (the recorded one standing for all), the planet's flank one
    cycles = np.array([(r, m, c) for r, m, c, *_ in rainflow.extract_cycles(force)])
    w_r, _ = _pow2_edges(cycles[:, 0])
    w_m, _ = _pow2_edges(cycles[:, 1])
    peaks = (np.floor(cycles[:, 1] / w_m) + 1) * w_m + 0.5 * (np.floor(cycles[:, 0] / w_r)
                                                             + 1) * w_r
    share = cycles[:, 2] / cycles[:, 2].sum()
    load = next(entry[3] for entry in pair_loads(case, rating, rating.rated_torque,
                                                 rating.rated_speed_rpm, 1.0)
                if entry[0] == "stage1.sun_mesh")
    one = FactorValue(1.0, "run", "run")
    base = dataclasses.replace(load, application_factor=one, load_sharing=one,
                               given={**load.given, "K_v": one})
    record = time[-1] - time[0]
    n_carrier = rating.rated_speed_rpm
    n_sun_rel = n_carrier * (56.0 / 19.0)
    contacts = {0: 3 * n_sun_rel * record / 60.0,  # sun: three planets
                1: n_sun_rel * 19.0 / 17.0 * record / 60.0}  # planet flank: one mesh
    hand = {0: 0.0, 1: 0.0}
    for peak, weight in zip(peaks, share):
        f_t = peak * math.cos(math.radians(20.0))  # spur: beta_b = 0
        gears = rate_pair(dataclasses.replace(base, torque1=f_t * 19 * 0.045 / 2.0)).gears
        for side in (0, 1):
            kind = load.materials[side].kind
            life = cycles_to_failure(kind, gears[side]["sigma_H"].value,
                                     gears[side]["sigma_HG_ref"].value, False)
            hand[side] += weight * contacts[side] / life
    scale = rating.service_life_h * 3600.0 / record
    # tolerance: the same sums in another order (a few hundred terms, ~1e-13)
    assert result.damage["stage1.sun"]["pitting"] == pytest.approx(hand[0] * scale, rel=1e-10)
    planet = result.damage["stage1.planet"]
    assert planet["source"].startswith("run's mesh forces")
    assert planet["pitting"] >= hand[1] * scale * (1 - 1e-10)  # the ring flank may rule
    # meshes the record does not hold keep the rated-load damage
    assert result.damage["stage2.sun"]["source"].startswith("rated load")


def test_peaks_of_a_bin_never_fall_below_the_cycles_own(nrel):
    case, rating = nrel
    ds, force, _ = _record(rating, seconds=0.2)
    matrix = duty_from_dataset(ds, "run.nc").matrices[0]
    peaks, counts = matrix.peaks()
    cycles = [(r, m, c) for r, m, c, *_ in rainflow.extract_cycles(force)]
    assert counts.sum() == pytest.approx(sum(c for *_, c in cycles), rel=1e-12)
    assert peaks.min() >= min(m + r / 2 for r, m, _ in cycles)
    assert peaks.max() >= max(m + r / 2 for r, m, _ in cycles)


@pytest.fixture(scope="module")
def streamed_run(tmp_path_factory):
    """The NREL gearbox loaded at its rated point for 0.1 s, streamed in small blocks
    with rainflow matrices of the mesh forces and the drive torque's load duration."""
    from pygear.model.case import load_case
    from pygear.model.reduction_settings import Reductions
    from pygear.runs import streaming
    from pygear.runs.transient_outputs import write_transient

    case = load_case("nrel5mw_gearbox")
    scene = case.scene("runup")
    reductions = Reductions(rainflow=("mesh_force",), load_duration=("drive_torque",),
                            bins=BINS)
    settings = dataclasses.replace(scene.transient, duration=0.1, mean_window=0.05,
                                   initial_speed_rpm=12.1, speed_reference_rpm=12.1,
                                   start_loaded=True, reductions=reductions)
    scene = dataclasses.replace(scene, transient=settings, analyses=("transient",))
    out = tmp_path_factory.mktemp("streamed")
    saved = streaming.BUFFER_BYTES
    streaming.BUFFER_BYTES = 512 * 8 * 30
    try:
        write_transient(case, scene, out, figure=False, stream=True)
    finally:
        streaming.BUFFER_BYTES = saved
    from pygear.io import open_dataset

    with open_dataset(out / "runup.nc") as ds:
        yield ds.load(), out / "runup.nc"


def test_streamed_reductions_give_the_whole_records_damage(nrel, streamed_run):
    case, rating = nrel
    run, _ = streamed_run
    whole = duty_from_dataset(run, "run.nc")  # counts the mesh_force record again
    reductions = duty_from_dataset(run.drop_vars("mesh_force"), "reductions.nc")
    assert reductions.notes["source"].startswith("reductions.nc: rainflow matrices")
    # the same mean speed: of the record, and the load duration's revolutions over its
    # time (every sample one interval; the damage takes contacts per second of record)
    assert reductions.speed_rpm == pytest.approx(whole.speed_rpm, rel=1e-9)
    a = rate_gearbox(case, rating, matrices=whole.matrices, record_s=whole.record_s,
                     record_speed_rpm=whole.speed_rpm)
    b = rate_gearbox(case, rating, matrices=reductions.matrices, record_s=reductions.record_s,
                     record_speed_rpm=reductions.speed_rpm)
    # same matrices (block-invariant power-of-two bins), same sums: round-off only; the
    # speeds differ in the last bits (a mean of the record against revolutions / time)
    for gear, values in a.damage.items():
        for kind in ("pitting", "bending"):
            assert b.damage[gear][kind] == pytest.approx(values[kind], rel=1e-9, abs=1e-300)
        assert values["source"].startswith("run's mesh forces")


def test_load_duration_of_the_reductions_is_a_duty_cycle(nrel, streamed_run):
    run, _ = streamed_run
    ldd = run.drop_vars([v for v in run.variables if v.startswith("rainflow_")
                         or v == "mesh_force"])
    duty = duty_from_dataset(ldd, "ldd.nc").duty_cycle
    interval = 1.0 / run.attrs["sample_rate"]
    # every sample stands for one interval of time; the speed is revolutions over time
    assert sum(duty.hours) * 3600.0 == pytest.approx(run.sizes["time"] * interval, rel=1e-10)
    speed = np.abs(run.speed.sel(member="rotor.body").values)
    hours = np.array(duty.hours)
    revolutions = speed.sum() * interval / 60.0
    assert (hours * np.array(duty.speed_rpm)).sum() * 60.0 == pytest.approx(revolutions,
                                                                           rel=1e-9)
    torque = np.abs(run.drive_torque.values)
    assert max(duty.torque) >= torque.max()


def test_cli_rates_a_run_file_and_an_openfast_output(streamed_run, tmp_path, capsys):
    _, path = streamed_run
    assert main(["rate", "nrel5mw_gearbox", "--dynamic-factor", "iso", "--duty-cycle",
                 str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["gears"]["stage1.sun"]["damage_from"].startswith("run's mesh forces")
    assert main(["rate", "nrel5mw_gearbox", "--dynamic-factor", "iso", "--duty-cycle",
                 "tests/data/nrel5mw_short.out", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["gears"]["stage1.sun"]["damage_from"].startswith("duty cycle")
    bad = tmp_path / "empty.nc"
    xr.Dataset({"x": ("t", [1.0, 2.0])}).to_netcdf(bad)
    assert main(["rate", "nrel5mw_gearbox", "--duty-cycle", str(bad)]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "holds no duty cycle" in error


def test_openfast_torque_and_speed_become_a_load_duration(nrel):
    # the rotor record's time at each level and its revolutions, by hand: the file's
    # eleven samples 0.05 s apart, each standing for half the interval to each side
    from pygear.io_openfast import read_openfast_output

    data = read_openfast_output("tests/data/nrel5mw_short.out")
    duty = duty_from_dataset(data, "short.out").duty_cycle
    t = data.time.values
    step = np.r_[0.5 * (t[1] - t[0]), 0.5 * (t[2:] - t[:-2]), 0.5 * (t[-1] - t[-2])]
    assert sum(duty.hours) * 3600.0 == pytest.approx(step.sum(), rel=1e-12)
    revolutions = (step * data.rotor_speed.values / 60.0).sum()
    assert (np.array(duty.hours) * 3600.0 * np.array(duty.speed_rpm) / 60.0).sum() == \
        pytest.approx(revolutions, rel=1e-12)
    assert max(duty.torque) >= data.rotor_torque.values.max()


def test_unknown_mesh_labels_are_refused(nrel):
    case, rating = nrel
    ds, _, _ = _record(rating, seconds=0.05)
    ds = ds.assign_coords(mesh=["stage9.sun-planet1"])
    found = duty_from_dataset(ds, "run.nc")
    with pytest.raises(CaseError, match=r"meshes \['stage9.sun-planet1'\] are not meshes"):
        rate_gearbox(case, rating, matrices=found.matrices, record_s=found.record_s)


def test_k_v_of_the_dynamic_model_enters_as_response(nrel, monkeypatch):
    case, rating = nrel
    import pygear.analysis.response as response

    given = {"stage1.sun_mesh": 1.21, "stage1.ring_mesh": 1.07, "stage2.sun_mesh": 1.11,
             "stage2.ring_mesh": 1.03, "parallel.mesh": 1.3}
    calls = []

    def fake(case_, speed, torque=None, **options):
        calls.append((speed, torque, options.get("keys")))
        return dict(given)

    monkeypatch.setattr(response, "dynamic_factors_at", fake)
    factors, method = gearbox_rating.model_dynamic_factors(case, rating)
    assert calls == [(rating.rated_speed_rpm, rating.rated_torque, "rating")]
    assert method.startswith("response analysis") and factors == given
    result = rate_gearbox(case, rating, dynamic_factors=factors, dynamic_factor_method=method)
    for entry in result.meshes:
        k_v = entry.rating.mesh["K_v"]
        assert k_v.source == "response" and k_v.value == given[entry.name]

    def refuse(*_, **__):
        raise CaseError("several stages need a multi-frequency balance")

    monkeypatch.setattr(response, "dynamic_factors_at", refuse)
    factors, method = gearbox_rating.model_dynamic_factors(case, rating)
    assert factors == {} and "cannot balance this case (several stages" in method
    result = rate_gearbox(case, rating, dynamic_factors=factors, dynamic_factor_method=method)
    assert {e.rating.mesh["K_v"].source for e in result.meshes} == {"computed"}


def test_tangential_load_of_a_helical_mesh_by_hand(nrel):
    # F_t = F cos(beta_b) cos(alpha_t): the helical pair's, from its helix angle
    from pygear.analysis.rating.run_damage import tangential_load

    case, rating = nrel
    load = next(entry[3] for entry in pair_loads(case, rating, rating.rated_torque,
                                                 rating.rated_speed_rpm, 1.0)
                if entry[0] == "parallel.mesh")
    gear = load.geometry.gear1
    beta = math.radians(abs(gear.helix_angle_deg))
    alpha_t = math.atan(math.tan(math.radians(gear.normal_pressure_angle_deg)) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    assert beta > 0.0
    assert tangential_load(load, 1000.0) == pytest.approx(
        1000.0 * math.cos(beta_b) * math.cos(alpha_t), rel=1e-12)
    assert abs(geo.base_helix_angle(gear)) == pytest.approx(beta_b, rel=1e-12)


def test_a_record_of_other_meshes_is_refused_before_the_model_runs(nrel, tmp_path, capsys,
                                                                   monkeypatch):
    import pygear.analysis.response as response

    case, rating = nrel
    ds, _, _ = _record(rating, seconds=0.05)
    path = tmp_path / "other.nc"
    ds.assign_coords(mesh=["stage9.sun-planet1"]).to_netcdf(path)

    def never(*_, **__):
        raise AssertionError("the dynamic model ran before the record was checked")

    monkeypatch.setattr(response, "dynamic_factors_at", never)
    assert main(["rate", "nrel5mw_gearbox", "--duty-cycle", str(path)]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "'stage9.sun-planet1'" in error


def test_a_batch_load_spectrum_a_year_is_rated_over_the_years(nrel, streamed_run, capsys):
    # the batch's yearly spectrum (pygear.runs.dlc_spectrum) of one load case standing
    # for h hours a year holds the run's counts times w = 3600 h / duration: its damage
    # over the life is the run's times w T / (8766 h) (T the span the run's counts
    # cover; the year's other hours idle), by hand
    from pygear.model.dlc_settings import HOURS_PER_YEAR, DesignLoadCases, LoadCase
    from pygear.runs.dlc_spectrum import load_spectrum

    case, rating = nrel
    run, path = streamed_run
    table = DesignLoadCases(scene="runup", wind_speeds=(11.4,), seeds=(1,),
                            duration=run.attrs["duration"])
    load = LoadCase(name="w11.4_s1", wind_speed=11.4, seed=1, hours_per_year=4000.0)
    with xr.open_dataset(path, decode_times=False) as raw:
        spectrum = load_spectrum([(raw.load(), load)], table)
    yearly = duty_from_dataset(spectrum, "load_spectrum.nc")
    assert yearly.record_s == pytest.approx(HOURS_PER_YEAR * 3600.0, rel=1e-15)
    single = duty_from_dataset(run.drop_vars("mesh_force"), "run.nc")
    a = rate_gearbox(case, rating, matrices=single.matrices, record_s=single.record_s,
                     record_speed_rpm=single.speed_rpm)
    b = rate_gearbox(case, rating, matrices=yearly.matrices, record_s=yearly.record_s,
                     record_speed_rpm=yearly.speed_rpm)
    share = 3600.0 * 4000.0 / table.duration * single.record_s / (HOURS_PER_YEAR * 3600.0)
    for gear, values in a.damage.items():
        assert b.damage[gear]["pitting"] == pytest.approx(values["pitting"] * share,
                                                          rel=1e-9, abs=1e-300)
    # the command reads the written spectrum (labels as pygear's indexes)
    written = path.parent / "load_spectrum.nc"
    spectrum.to_netcdf(written)
    assert main(["rate", "nrel5mw_gearbox", "--dynamic-factor", "iso", "--duty-cycle",
                 str(written), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["gears"]["stage1.sun"]["damage"] == pytest.approx(
        b.damage["stage1.sun"]["pitting"], rel=1e-12)
    # its load duration distribution: the year's hours, idle ones included
    duty = duty_from_dataset(spectrum.drop_vars(
        [v for v in spectrum.data_vars if v.startswith("rainflow_")]), "ldd.nc").duty_cycle
    assert duty.period_h == HOURS_PER_YEAR
    assert sum(duty.hours) == pytest.approx(4000.0 * run.sizes["time"]
                                            / run.attrs["sample_rate"] / table.duration,
                                            rel=1e-9)
