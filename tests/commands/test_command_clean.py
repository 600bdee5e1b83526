"""The clean command's contract in the library (:mod:`marinecdpr.commands.clean`): its spec
and its rules on options that go together checked without the command line, the estimate's
refusals and counts, the command line's defaults the spec's, runs from Python giving the
command's files byte for byte (the plain job with its comparison and hull, the surface, the
sea states), and docs/commands/clean.md run as written (issue 38, items 1 and 7)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import clean as command
from marinecdpr.commands.clean import CleanSpec
from marinecdpr.errors import ScenarioError

from command_pages import assert_table_is_the_spec, cli_default, options_table, page, run_page

runner = CliRunner()


@pytest.fixture(scope="module")
def paper_clean():
    return marinecdpr.load_scenario("paper_clean")


@pytest.mark.parametrize("options, field, words", [
    ({"plant": "steam"}, "plant", "plant steam: expected mujoco or own"),
    ({"duration": 0.0}, "duration", "duration 0: expected a positive number"),
    ({"hull_area": -5.0}, "hull_area", "hull_area -5: expected a positive number"),
    ({"move_time": -1.0}, "move_time", "move_time -1: expected a non-negative number"),
    ({"headings": "0,360"}, "headings", "a heading is given twice (headings are taken modulo 360 deg)"),
    ({"headings": "north"}, "headings", "expected numbers separated by commas, e.g. 180,150"),
    ({"coverage_target": 120.0}, "coverage_target", "coverage_target 120: expected a percentage between 0 and 100"),
    ({"in_band_target": float("nan")}, "in_band_target", "expected a percentage between 0 and 100"),
    ({"workers": 0}, "workers", "workers 0: expected a positive whole number of worker processes"),
    ({"workers": 10_000}, "workers", "gains nothing (each is a process of its own)"),
    ({"hull_area": 1e308}, "hull_area", "hull_area 1e+308 / --move-time 600: hull_area_m2 must be a positive number "
                                        "of m2 up to 1e+06, got 1e+308"),
    ({"hull_area": 100.0, "move_time": 1e300}, "hull_area", "move_time_s must be a number of seconds from 0 to 1e+06"),
    ({"surface": True, "move_time": 1e308}, "move_time", "move_time 1e+308: must be a number of seconds from 0 to "
                                                         "1e+06 to move the frame to its next placement"),
    ({"hull_aera": 5.0}, "hull_aera", "no such option of CleanSpec"),
    ({"fly_runs": "some"}, "fly_runs", "fly_runs some: expected first or all"),
    ({"fly_runs": "all"}, "fly_runs", "fly_runs all: goes with --rail and a --rail-mode that runs the carriage"),
    ({"surface": True, "rail": True, "rail_mode": "stepped", "fly_runs": "all"}, "fly_runs",
     "goes with --rail and a --rail-mode that runs the carriage continuously (fastest or continuous)"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        CleanSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert words in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("options, line", [
    ({"surface": True, "hull_area": 2200.0},
     "--surface with --hull-area 2200: choose one (--surface has the hull's real placements)"),
    ({"surface": True, "seas": True}, "--surface with --seas: cannot go together yet: its hours are for the "
                                      "scenario's sea"),
    ({"surface": True, "scatter": "my.csv"}, "--surface with --scatter my.csv: cannot go together yet"),
    ({"guarantee": True, "seas": True}, "--guarantee with --seas: cannot go together: it sets the lanes from one "
                                        "sea state's run"),
    ({"serial": True, "workers": 2}, "--workers 2: cannot go with --serial (--workers and --scheduler run on Dask)"),
    ({"serial": True, "scheduler": "tcp://h:8786"}, "--scheduler tcp://h:8786: cannot go with --serial"),
])
def test_options_that_do_not_go_together_name_the_option_to_change(options, line):
    with pytest.raises(SpecError) as err:
        CleanSpec(**options)
    shown = f"{err.value.flag} {err.value.value}: {err.value.detail}"  # the command line's line
    assert shown.startswith(line)
    for name, value in options.items():  # each alone is fine
        assert getattr(CleanSpec(**{name: value}), name) is not None


def test_the_spec_s_defaults_are_the_studies_and_scatter_implies_seas():
    from marinecdpr.studies.cleaning import COVERAGE_TARGET_PCT, IN_BAND_TARGET_PCT

    spec = CleanSpec()
    assert (spec.coverage_target, spec.in_band_target) == (COVERAGE_TARGET_PCT, IN_BAND_TARGET_PCT)
    assert not spec.over_seas and CleanSpec(scatter="x.csv").over_seas and CleanSpec(seas=True).over_seas
    assert spec.processes == 2 and CleanSpec(workers=3).processes == 3 and CleanSpec(serial=True).processes == 1
    assert CleanSpec(headings="180,90").headings == (180.0, 90.0) == CleanSpec(headings=[180, 90]).headings


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``clean`` but the scenario and --out has the spec's field and default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["clean"].params}
    options = set(params) - {"scenario", "out"}
    assert options == set(CleanSpec.model_fields)
    for name in options:
        default = cli_default(params[name])
        spec_default = CleanSpec.default(name)
        assert (CleanSpec(**{name: default}).model_dump()[name] if default is not None else None) == spec_default


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    """A rule on options that go together reaches the user as the spec words it: one line, exit 2, nothing written."""
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["clean", "paper_clean", "--surface", "--hull-area", "2200", "--out", str(tmp_path / "o")],
                        terminal_width=4000)
    assert one_line_exit_2(res) == "error: --surface with --hull-area 2200: choose one (--surface has the hull's real " \
                                   "placements)"
    assert not (tmp_path / "o").exists()


def test_the_estimate_refuses_what_is_no_cleaning_job_or_no_sea(paper_clean, tmp_path):
    with pytest.raises(ScenarioError, match="no cleaning job"):
        command.estimate(CleanSpec(), marinecdpr.load_scenario("paper"))
    still = paper_clean.with_changes(base_motion={"type": "still"})
    command.estimate(CleanSpec(duration=0.2), still)  # a still ship cleans
    with pytest.raises(ScenarioError, match="sea_state"):
        command.estimate(CleanSpec(seas=True, duration=0.2), still)
    bad = tmp_path / "bad.csv"
    bad.write_text("hs_m,tp_s,probability\n0.5,6,0.3\n")
    with pytest.raises(ScenarioError, match="bad.csv"):
        command.estimate(CleanSpec(scatter=bad, duration=0.2), paper_clean)


def test_the_estimate_counts_the_runs_and_says_what_it_will_not_do(paper_clean, tmp_path):
    """The job's runs: 1, 2 with the guarantee, and the compared variants (calm water only on a
    moving ship, no brush drag); the scenario's own duration where more was asked; over the seas
    the sea states times headings, and a PARTIAL job where the path outlasts the run."""
    from marinecdpr.motion.trajectory import cleaning_path

    n = paper_clean.time.n_steps
    est = command.estimate(CleanSpec(), paper_clean)
    assert est.runs == 3 and est.flown is paper_clean and est.warnings("x") == []
    assert command.estimate(CleanSpec(guarantee=True, compare=False), paper_clean).runs == 2
    assert command.estimate(CleanSpec(), paper_clean.with_changes(base_motion={"type": "still"})).runs == 2
    short = command.estimate(CleanSpec(duration=0.5), paper_clean)
    assert short.flown.time.duration_s == 0.5 and short.flown.time.n_steps < n and short.size.n_steps == \
        short.flown.time.n_steps
    long = command.estimate(CleanSpec(duration=1e4), paper_clean)
    lasts = paper_clean.time.duration_s
    assert long.flown.time.duration_s == lasts
    assert long.warnings("my_job") == [f"--duration 10000: my_job lasts {lasts:g} s; flying those {lasts:g} s"]
    csv = tmp_path / "two.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,0.5\n1.0,6,0.0\n1.0,8,0.5\n")
    seas = command.estimate(CleanSpec(scatter=csv, headings="180,150,120", duration=1.0), paper_clean)
    assert seas.cells == 2 * 3 and seas.steps == 6 * seas.flown.time.n_steps * 100
    assert seas.executor.name == "serial" and seas.executor.why == "small"  # 6 cells of 1 s: too small for Dask
    assert command.estimate(CleanSpec(scatter=csv, duration=1.0, serial=True), paper_clean).executor.why == "asked"
    path_s = paper_clean.trajectory.start_time_s + cleaning_path(paper_clean.cleaning).duration_s
    assert seas.path_s == path_s and seas.warnings() == [
        f"paper_clean: a PARTIAL job: each sea state flies the first 1 s of the {path_s:.4g} s path; its coverage "
        "and hours are that part's"]


def _same_files(a: Path, b: Path, names) -> None:
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_a_run_from_python_writes_what_the_command_writes(paper_clean, tmp_path):
    """The job, its comparison with calm water and no brush drag, and the hull's hours: the
    result's summary holds each of its parts, and its files are the command's byte for byte."""
    spec = CleanSpec(duration=0.2, plant="own", hull_area=100.0)
    est = command.estimate(spec, paper_clean)
    seen = []
    result = command.run(spec, paper_clean, estimated=est, progress=lambda d, t: seen.append((d, t)))
    n = est.flown.time.n_steps
    assert seen[-1] == (3 * n, 3 * n) and all(t == 3 * n for _, t in seen)  # three runs on one count
    s = result.summary()
    assert list(s)[-2:] == ["comparison", "hull"] and "comparison" not in result.job.summary
    assert s["comparison"]["as asked"]["coverage_pct"] == result.job.summary["coverage_pct"]
    cleaned = s["panel_area_m2"] - s["missed_area_m2"]
    assert result.hull["placements"] == math.ceil(100.0 / cleaned - 1e-9)
    assert result.bypassed() == []
    result.write(tmp_path / "py")
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "0.2", "--plant", "own", "--hull-area", "100",
                              "--out", str(tmp_path / "cli")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert json.loads((tmp_path / "py" / "summary.json").read_text()) == json.loads(json.dumps(s))
    _same_files(tmp_path / "py", tmp_path / "cli", ["clean.csv", "summary.json", "report.html"])
    for sentence in result.findings():
        assert sentence in res.stdout


def _short_band(tmp_path: Path) -> Path:
    """paper_clean.toml with its band cut to the 15 m at the stern (of its 190 m: the tiling's
    time is the band's), beside the files it reads."""
    import shutil

    builtin = Path(marinecdpr.__file__).parent / "scenario" / "builtin"
    for data in builtin.glob("*.csv"):
        shutil.copy(data, tmp_path / data.name)
    text = (builtin / "paper_clean.toml").read_text()
    assert text.count("stations_m = [-95.0, 95.0]") == 1
    path = tmp_path / "short_band.toml"
    path.write_text(text.replace("stations_m = [-95.0, 95.0]", "stations_m = [-95.0, -80.0]"))
    return path


@pytest.mark.figures
def test_the_surface_from_python_is_what_the_command_writes(tmp_path):
    """On a short band (the stern's 15 m: the curved end, placements cut to its flare), the
    command's files are the run's from Python byte for byte."""
    scenario = _short_band(tmp_path)
    spec = CleanSpec(duration=0.2, plant="own", surface=True, compare=False)
    shares = []
    placed = command.tile(spec, marinecdpr.load_scenario(str(scenario)), progress=shares.append)
    assert shares[-1] == pytest.approx(1.0, abs=1e-12) and placed.move_time_s == 600.0
    result = command.run(spec, marinecdpr.load_scenario(str(scenario)), placed=placed)
    assert result.summary()["surface"] == placed.summary() and result.comparison is None
    names = [p.name for p in result.write(tmp_path / "py")]
    assert names[-2:] == ["placements.csv", "surface.png"]
    res = runner.invoke(app, ["clean", str(scenario), "--duration", "0.2", "--plant", "own", "--surface",
                              "--no-compare", "--out", str(tmp_path / "cli")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    _same_files(tmp_path / "py", tmp_path / "cli", ["placements.csv", "clean.csv", "summary.json"])


def test_the_seas_from_python_are_what_the_command_writes(paper_clean, tmp_path):
    csv = tmp_path / "one.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,1.0\n")
    spec = CleanSpec(scatter=csv, duration=0.2, plant="own", coverage_target=0.0, headings="180,90", serial=True)
    result = command.run(spec, paper_clean)
    assert isinstance(result, command.CleanSeasResult) and len(result.seas.sea.results) == 2
    assert result.executor.name == "serial" and result.seas.sea.executor == "serial"
    s = result.summary()
    assert s["sea_states"] == 2 and s["coverage_target_pct"] == 0.0
    assert s["operability"] == result.seas.sea.operability
    result.write(tmp_path / "py")
    res = runner.invoke(app, ["clean", "paper_clean", "--scatter", str(csv), "--duration", "0.2", "--plant", "own",
                              "--coverage-target", "0", "--headings", "180,90", "--serial", "--out",
                              str(tmp_path / "cli")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert json.loads((tmp_path / "py" / "summary.json").read_text()) == json.loads(json.dumps(s))
    _same_files(tmp_path / "py", tmp_path / "cli", ["sea_states.csv", "summary.json"])


# ------------------------------------------------------------------ the page
@pytest.mark.figures
def test_the_page_lists_the_spec_s_options_and_defaults():
    assert_table_is_the_spec("clean", CleanSpec)


@pytest.mark.figures
def test_the_page_runs_as_written(tmp_path, monkeypatch):
    ns = run_page("clean", tmp_path, monkeypatch)
    result, est = ns["result"], ns["est"]
    assert est.runs == 1 and est.warnings() == []
    s = json.loads((tmp_path / "out" / "clean" / "summary.json").read_text())
    assert s["coverage_pct"] == ns["coverage"] == result.job.summary["coverage_pct"] > 0.0
    cleaned = s["panel_area_m2"] - s["missed_area_m2"]
    assert s["hull"]["placements"] == ns["placements"] == math.ceil(2200.0 / cleaned - 1e-9)
    assert [p.name for p in ns["files"]] == ["clean.csv", "coverage.png", "cleaning.png", "summary.json",
                                             "report.html"]
    assert ns["said"] == ("--surface", "with --hull-area 2200")


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_rail_strip_from_python_is_what_the_command_writes(tmp_path):
    """``--surface --rail`` on examples/rail_strip.toml: the command's strip is the study's
    (:func:`~marinecdpr.studies.strip.rail_strip` over the flown horizon), its stations.csv
    one row per visit whose hours add up to the summary's, the same files as the command
    line writes."""
    from marinecdpr.studies.strip import rail_strip

    sc = marinecdpr.load_scenario(str(EXAMPLES / "rail_strip.toml"))
    spec = CleanSpec(duration=0.2, plant="own", surface=True, rail=True, rail_mode="stepped", compare=False)
    est = command.estimate(spec, sc)
    placed = command.tile(spec, est.flown)
    result = command.run(spec, sc, estimated=est, placed=placed)
    assert result.surface is None and result.strip is placed
    s = result.summary()["strip"]
    assert s == rail_strip(est.flown).summary()
    assert s["rail_stations"] == 9 and s["crane_placements"] == 4 and s["partial"]
    names = [p.name for p in result.write(tmp_path / "py")]
    assert names[-2:] == ["stations.csv", "stretches.csv"]
    rows = np.genfromtxt(tmp_path / "py" / "stations.csv", delimiter=",", names=True)
    assert rows.size == 13 and rows["hours"].sum() == pytest.approx(s["hours"], rel=1e-9)
    assert int(rows["by_crane"].sum()) == s["moves"]["crane"] == 4
    res = runner.invoke(app, ["clean", str(EXAMPLES / "rail_strip.toml"), "--duration", "0.2", "--plant", "own",
                              "--surface", "--rail", "--rail-mode", "stepped", "--no-compare", "--out",
                              str(tmp_path / "cli")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert "by crane: stations -12 to -10 m (aft of the rail's reach): 4 placements, 4 crane moves" in res.output
    _same_files(tmp_path / "py", tmp_path / "cli", ["stations.csv", "stretches.csv", "clean.csv", "summary.json"])


def test_the_rail_strip_by_default_takes_the_faster_mode_per_stretch(tmp_path):
    """``--surface --rail`` without ``--rail-mode`` on examples/rail_strip.toml: its one stretch
    of the rail (10 m) cleaned while the carriage moves, 570.65 s against 988.4 s stepped;
    stations.csv's run row holds the run's cleaning, stretches.csv both hours and the mode,
    and the command prints one line on it; the run is flown closed loop over the horizon: its
    figures in the strip's summary are continuous_flight.csv's, and a line says them."""
    res = runner.invoke(app, ["clean", str(EXAMPLES / "rail_strip.toml"), "--duration", "0.2", "--plant", "own",
                              "--surface", "--rail", "--no-compare", "--out", str(tmp_path / "cli")],
                        terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert ("rail stretch s = 0 to 10 m: continuous (fastest asked); stepped 0.2746 h, continuous 0.1585 h at "
            "1.97 cm/s") in res.output
    assert "continuous runs: stand-off 3.39 to 3.45 mm, normal force on the hull 59.93 to 60.24 N" in res.output
    s = json.loads((tmp_path / "cli" / "summary.json").read_text())["strip"]
    assert s["rail_mode"] == "fastest" and s["rail_stations"] == 0 and len(s["continuous_runs"]) == 1
    (stretch,) = s["rail_stretches"]
    assert stretch["mode"] == "continuous" and stretch["continuous_h"] < 0.6 * stretch["stepped_h"]
    rows = np.genfromtxt(tmp_path / "cli" / "stations.csv", delimiter=",", names=True)
    assert rows.size == 5 and rows["hours"].sum() == pytest.approx(s["hours"], rel=1e-9)
    assert rows["clean_s"][-1] == pytest.approx(s["continuous_runs"][0]["duration_s"], rel=1e-9)
    table = np.genfromtxt(tmp_path / "cli" / "stretches.csv", delimiter=",", names=True)
    assert table["continuous"] == 1 and table["stepped_h"] == pytest.approx(stretch["stepped_h"], rel=1e-9)
    g = s["continuous_flight"]
    flight = np.genfromtxt(tmp_path / "cli" / "continuous_flight.csv", delimiter=",", names=True)
    assert flight.size == g["steps"] == 201 and g["plant"] == "own" and g["partial"]
    assert g["normal_force_in_band_pct"] == pytest.approx(100.0 * flight["in_band"].mean(), rel=1e-12)
    assert g["max_tracking_error_m"] == pytest.approx(flight["tracking_error_m"].max(), rel=1e-9)
    assert g["tension_min_N"] == pytest.approx(min(flight[f"T{i}_N"].min() for i in range(1, 5)), rel=1e-9)
    assert g["normal_force_N"] == pytest.approx([flight["normal_force_N"].min(), flight["normal_force_N"].max()],
                                                rel=1e-9)
    assert ("continuous run flown closed loop (own, 0.201 s of its 570.7 s, PARTIAL): normal force in band 100 % "
            "(59.93 to 60.24 N on the hull)") in res.output and "controller held" in res.output
    res = runner.invoke(app, ["clean", str(EXAMPLES / "rail_strip.toml"), "--surface", "--rail", "--rail-mode",
                              "sideways", "--out", str(tmp_path / "bad")])
    assert res.exit_code == 2 and len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert res.stderr.strip() == "error: --rail-mode sideways: expected fastest, stepped or continuous"
    assert not (tmp_path / "bad").exists()


def test_rail_without_a_carriage_is_one_line_exit_2(tmp_path):
    res = runner.invoke(app, ["clean", "paper_clean", "--surface", "--rail", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "ship.carriage: missing: clean --rail steps the frame along" in lines[0]
    assert not (tmp_path / "o").exists()
    res = runner.invoke(app, ["clean", "paper_clean", "--rail", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and res.stderr.strip().splitlines() == [
        "error: --rail without --surface: --rail cleans the [cleaning.surface] band from the carriage's rail: "
        "give --surface too"], res.stderr
