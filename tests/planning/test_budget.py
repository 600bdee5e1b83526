"""Run sizes (issue 9): runs too big for memory or time are refused up front, and
``marinecdpr plan`` streams its plan through plan.csv and the tension figure in chunks."""

from __future__ import annotations

import resource
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
import tripwire
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError

runner = CliRunner()
SCENARIOS = Path(marinecdpr.__file__).parent / "scenario" / "builtin"
LIMIT_AS = 4 * 2**30  # a runaway allocation in the child fails instead of eating the machine


def _scenario(tmp_path: Path, name: str, replace: dict[str, str], base: str = "paper") -> Path:
    """A built-in scenario with lines edited (each old text once in the file)."""
    text = (SCENARIOS / f"{base}.toml").read_text()
    for old, new in replace.items():
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    # the built-in's own files (an RAO table) stay where they are
    text = text.replace('file = "paper_sea_rao.csv"', f'file = "{SCENARIOS / "paper_sea_rao.csv"}"')
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _cli(*args: str, timeout: float = 300.0) -> tuple[int, list[str]]:
    """Exit code and stderr lines of the command in a child process whose memory is capped
    (a run that tried to allocate its size would fail, not refuse) and whose work is
    tripwired (:mod:`tripwire`: a run that started its work exits 99 naming where)."""

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (LIMIT_AS, LIMIT_AS))

    proc = tripwire.run_cli(*args, preexec_fn=cap, timeout=timeout)
    return proc.returncode, proc.stderr.strip().splitlines()


def _refused(code: int, lines: list[str], *parts: str) -> None:
    """One line, exit 2, before any work (arithmetic, not allocation: no tripwire crossed)."""
    assert code != tripwire.TRIPPED, lines
    assert code == 2, lines[-5:]
    assert len(lines) == 1 and lines[0].startswith("error: "), lines
    for part in parts:
        assert part in lines[0], lines[0]


def test_the_tripwires_catch_a_run_that_starts(tmp_path):
    # the check above is not vacuous: a run that is not refused crosses one at once
    code, lines = _cli("plan", "paper", "--out", str(tmp_path / "o"))
    assert code == tripwire.TRIPPED and lines[-1].startswith("work started: marinecdpr."), lines
    assert not (tmp_path / "o" / "plan.csv").exists()


# ----------------------------------------------------------------- refused up front
def test_plan_with_a_tiny_step_over_days_is_refused_with_its_size(tmp_path):
    scen = _scenario(tmp_path, "fine", {"step_s = 0.001": "step_s = 1e-5", "duration_s = 15.0": "duration_s = 1e6"})
    code, lines = _cli("plan", str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines, "time.step_s", "1e+11 steps of 1e-05 s over 1e+06 s",
             "sane time", "use a longer step_s")
    assert not (tmp_path / "o").exists()


def test_plan_of_a_long_duration_is_refused_with_its_size(tmp_path):
    scen = _scenario(tmp_path, "long", {"duration_s = 15.0": "duration_s = 1e6"})
    code, lines = _cli("plan", str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines, "time.duration_s", "1,000,000,001 steps of 0.001 s", "use a shorter duration_s")


def test_simulate_of_a_long_duration_is_refused_with_its_memory(tmp_path):
    scen = _scenario(tmp_path, "long", {"duration_s = 15.0": "duration_s = 1e5"})
    code, lines = _cli("simulate", str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines, "time.duration_s", "100,000,001 steps", "GB in memory", "this machine:")
    assert not (tmp_path / "o").exists()


def test_workspace_of_a_huge_grid_is_refused_with_its_memory(tmp_path):
    code, lines = _cli("workspace", "paper", "--points", "100000x100000", "--out", str(tmp_path / "o"))
    _refused(code, lines, "1e+10 poses (100000 x 100000)", "TB in memory", "fewer grid points")
    assert not (tmp_path / "o").exists()


def test_sea_state_summed_too_often_is_refused(tmp_path):
    # a 3 h record of 8100 wave components, summed at 21.6 M times: about 5 h of work
    scen = _scenario(tmp_path, "sea", {"record_s = 1800.0 ": "record_s = 10800.0 ", "step_s = 0.001": "step_s = 0.0005",
                                       "duration_s = 15.0": "duration_s = 10800.0"}, base="paper_sea")
    code, lines = _cli("plan", str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines, "base_motion.record_s", "8,100 wave components", "component-samples",
             "use a shorter record_s")


@pytest.mark.parametrize("command, replace", [
    ("plan", {"step_s = 0.001": "step_s = 1e-12"}),
    ("plan", {"duration_s = 15.0": "duration_s = 1e12"}),
    ("simulate", {"duration_s = 15.0": "duration_s = 1e12"}),
])
def test_absurd_times_are_one_line_exit_2(tmp_path, command, replace):
    scen = _scenario(tmp_path, "absurd", replace)
    code, lines = _cli(command, str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines)


def test_absurd_sea_record_is_one_line_exit_2(tmp_path):
    scen = _scenario(tmp_path, "absurd", {"record_s = 1800.0 ": "record_s = 1e12 "}, base="paper_sea")
    code, lines = _cli("plan", str(scen), "--out", str(tmp_path / "o"))
    _refused(code, lines, "record_s")


def test_library_refuses_before_allocating(paper, monkeypatch):
    from marinecdpr.prototype import simulation  # noqa: F401 - imported before the tripwires, patched too
    from marinecdpr.studies.workspace import workspace_map

    fine = paper.with_changes(time={"step_s": 1e-5, "duration_s": 1e6})
    with monkeypatch.context() as armed:
        tripwire.arm(armed)  # the refusal comes before any work (not: within a second)
        for call in (lambda: marinecdpr.plan(fine), lambda: marinecdpr.simulate(fine, plant="own"),
                     lambda: workspace_map(paper, n=(100000, 100000))):
            with pytest.raises(ScenarioError, match="in memory") as info:
                call()
            assert "\n" not in str(info.value)
        with pytest.raises(tripwire.WorkStarted):  # and the tripwires do catch work
            marinecdpr.plan(paper)
    with pytest.raises(ScenarioError) as info:
        marinecdpr.plan(fine)
    assert info.value.key == "time.step_s" and "TB in memory" in str(info.value)


def test_estimates_and_the_machine(paper):
    from marinecdpr.planning.budget import check_run_size, estimate_run, human_bytes, machine_memory_bytes

    assert machine_memory_bytes() > 2**28
    assert [human_bytes(x) for x in (512, 2.4e12, 15.2e9, 397e9)] == ["512 B", "2.4 TB", "15 GB", "397 GB"]
    size = check_run_size(paper, "plan")  # the paper's plan fits anywhere
    assert size.n_steps == 15001 and size.work == 4 * 15001
    # in memory a plan grows with its steps; streamed it does not
    hour = paper.with_changes(time={"step_s": 0.001, "duration_s": 3600.0})
    long = paper.with_changes(time={"step_s": 0.001, "duration_s": 36000.0})
    assert estimate_run(long, "plan").memory_bytes > 5 * estimate_run(hour, "plan").memory_bytes
    assert estimate_run(long, "plan_stream").memory_bytes == estimate_run(hour, "plan_stream").memory_bytes
    check_run_size(long, "plan_stream")
    with pytest.raises(ScenarioError, match=r"this machine: 4 GiB, a run may use 75%\); use a shorter duration_s"):
        check_run_size(long, "plan", memory_bytes=4 * 2**30)


# ------------------------------------------------------------------ plan in chunks
def _heavy(tmp_path: Path, mass: str, duration: str) -> Path:
    return _scenario(tmp_path, f"heavy{mass}", {"mass_kg = 5.0": f"mass_kg = {mass}",
                                                "duration_s = 15.0": f"duration_s = {duration}"})


@pytest.mark.parametrize("mass, duration", [("200.0", "0.5"), ("12.0", "7.5")])
def test_streamed_plan_files_are_the_in_memory_ones(tmp_path, mass, duration):
    from marinecdpr.planning.planner import iter_plan
    from marinecdpr.report.writers import write_plan_csv, write_plan_stream

    sc = marinecdpr.load_scenario(_heavy(tmp_path, mass, duration))
    whole = marinecdpr.plan(sc)
    assert not whole.all_feasible
    write_plan_csv(whole, sc, tmp_path / "whole.csv")
    summary = write_plan_stream(iter_plan(sc, chunk_steps=64), sc, tmp_path / "streamed.csv",
                                tmp_path / "streamed.png")
    assert (tmp_path / "streamed.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    assert (tmp_path / "streamed.png").read_bytes()[:4] == b"\x89PNG"
    assert summary.n_steps == whole.n_steps and summary.n_feasible == int(whole.feasible.sum())
    assert summary.pinv_range == (np.nanmin(whole.tensions_pinv), np.nanmax(whole.tensions_pinv))
    finite = whole.tensions[np.isfinite(whole.tensions)]
    expected = (finite.min(), finite.max()) if finite.size else (np.nan, np.nan)
    np.testing.assert_array_equal(summary.tension_range, expected)
    assert summary.infeasibility() == whole.infeasibility()


@pytest.mark.figures
def test_plan_command_writes_in_chunks_without_the_whole_plan(tmp_path, monkeypatch):
    from marinecdpr.planning import planner as planning
    from marinecdpr.report.writers import write_plan_csv

    scen = _heavy(tmp_path, "12.0", "7.5")
    sc = marinecdpr.load_scenario(scen)
    whole = marinecdpr.plan(sc)
    write_plan_csv(whole, sc, tmp_path / "whole.csv")

    def no_whole_plan(*args, **kwargs):
        raise AssertionError("the command built the whole plan in memory")

    monkeypatch.setattr(planning, "plan", no_whole_plan)
    monkeypatch.setattr(planning, "plan_at", no_whole_plan)
    monkeypatch.setattr(planning, "DEFAULT_CHUNK_STEPS", 100)  # 76 chunks
    pieces = []
    real_iter = planning.iter_plan

    def counting(*args, **kwargs):
        for piece in real_iter(*args, **kwargs):
            pieces.append(piece.n_steps)
            yield piece

    monkeypatch.setattr(planning, "iter_plan", counting)
    res = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o")])
    assert res.exit_code == 3, res.output
    assert len(pieces) == 76 and max(pieces) == 100
    assert (tmp_path / "o" / "plan.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    assert (tmp_path / "o" / "tensions.png").read_bytes()[:4] == b"\x89PNG"
    assert res.stderr.strip() == f"infeasible: {sc.name}: {whole.infeasibility()}"
    finite = whole.tensions[np.isfinite(whole.tensions)]
    assert f"{int(whole.feasible.sum())} of {whole.n_steps}" in res.stdout
    assert (f"{np.nanmin(whole.tensions_pinv):.2f} .. {np.nanmax(whole.tensions_pinv):.2f}" in res.stdout
            and f"{finite.min():.2f} .. {finite.max():.2f}" in res.stdout)


def test_tension_envelope_keeps_every_extreme(paper_plan):
    from marinecdpr.report.figures import TensionEnvelope
    from marinecdpr.planning.planner import iter_plan

    env = TensionEnvelope(paper_plan.n_steps, 4, columns=97)
    for piece in iter_plan(marinecdpr.load_scenario("paper"), chunk_steps=1000):
        env.add(piece)
    trace = env.trace()
    assert trace.t.size == 2 * 97 and trace.t[0] == 0.0 and trace.t[-1] == paper_plan.t[-1]
    for name in ("tensions_pinv", "tensions"):
        full, kept = getattr(paper_plan, name), getattr(trace, name)
        np.testing.assert_array_equal(kept.min(axis=0), full.min(axis=0))
        np.testing.assert_array_equal(kept.max(axis=0), full.max(axis=0))
    # a plan no longer than the columns keeps every step as it is
    short = TensionEnvelope(501, 4)
    piece = next(iter_plan(marinecdpr.load_scenario("paper"), chunk_steps=501))
    short.add(piece)
    np.testing.assert_array_equal(short.trace().tensions, piece.tensions)
    np.testing.assert_array_equal(short.trace().t, piece.t)


# -------------------- formerly tests/test_issue21_run_budgets.py

"""Issue 21, items 16 and 17: the newer commands size their work before they start it and
refuse, in one line with the estimate and the option to change, what the machine cannot
hold or finish (a BEM of millions of panels, a latency measurement of a billion calls, a
control study or a cleaning job over sea states of billions of steps), as plan does; and
their bad values are one line, exit 2, never a traceback."""

import math

import pytest
from typer.testing import CliRunner

from conftest import one_line_exit_2

from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.bem import bem_panels
from marinecdpr.planning.budget import (MAX_BEM_S, MAX_LATENCY_CALLS, check_bem_size, check_latency_calls,
                                        estimate_bem, human_bytes)

runner = CliRunner()
GIB = 2**30
RAO = ["rao", "--length", "100", "--beam", "20", "--draught", "5", "--gm", "2"]


# ------------------------------------------------------------------ the BEM's size
@pytest.mark.parametrize("shape, dims, panel, panels", [
    # counted by hand: box (n_x, n_y, n_z) = (40, 8, 4): bottom 320, sides 2 (40 + 8) 2 = 192
    ("box", (100, 20, 5), 2.5, 512),
    # (63, 13, 7): bottom 819, the sides' 3 rows below the waterline and the clipped 4th, 2 (63 + 13) 5
    ("box", (100, 20, 5), 1.6, 1579),
    # Wigley: n_x = 40, the girth's 5 panels: 2 40 5
    ("wigley", (100, 20, 5), 2.5, 400),
    ("box", (100, 1e5, 5), 2.0, 50 * 50000 + 2 * 50050 * 4),
])
def test_the_bem_panels_are_counted_before_any_mesh(shape, dims, panel, panels):
    L, B, T = dims
    assert bem_panels(shape=shape, length_m=L, beam_m=B, draught_m=T, panel_m=panel) == panels


def test_the_panel_count_is_the_mesh_s():
    pytest.importorskip("capytaine")
    import capytaine as cpt

    from marinecdpr.motion.bem import _box_resolution, wigley_mesh

    for L, B, T, p in ((100, 20, 5, 1.6), (50, 8, 3, 0.7), (30, 10, 2, 3.3)):
        box = cpt.FloatingBody(mesh=cpt.mesh_parallelepiped(size=(L, B, 2 * T), center=(0, 0, 0),
                                                            resolution=_box_resolution(L, B, T, p))).immersed_part()
        assert box.mesh.nb_faces == bem_panels(shape="box", length_m=L, beam_m=B, draught_m=T, panel_m=p)
        assert wigley_mesh(length_m=L, beam_m=B, draught_m=T, panel_m=p).nb_faces == \
            bem_panels(shape="wigley", length_m=L, beam_m=B, draught_m=T, panel_m=p)


def test_the_bem_estimate_by_hand():
    size = estimate_bem(shape="box", length_m=100, beam_m=20, draught_m=5, panel_m=2.5, frequencies=33, headings=4)
    n = 512
    assert size.panels == n and size.memory_bytes == 300e6 + 64 * n * n
    assert size.seconds == pytest.approx(33 * (5e-7 * n * n + 1e-10 * n ** 3 + 2e-8 * n * n * 10))
    assert size.seconds < 10  # docs/performance.md's default hull: started
    check_bem_size(shape="box", length_m=100, beam_m=20, draught_m=5, panel_m=2.5, frequencies=33, headings=4,
                   memory_bytes=8 * GIB)


@pytest.mark.parametrize("args, words", [
    (["--beam", "1e5", "--panel", "2"], ["a BEM of 2,900,400 panels", "would need about 538 TB in memory",
                                         "use a larger --panel"]),
    (["--hull", "wigley", "--panel", "0.1"], ["a BEM of 234,000 panels (wigley hull of 100 x 20 x 5 m at 0.1 m",
                                              "use a larger --panel"]),
    (["--panel", "0.5"], ["a BEM of 12,800 panels", "at 33 frequencies and 4 headings would take about",
                          "more than the 60 min a run may take", "fewer --omega frequencies"]),
    (["--panel", "1e-320"], ["a BEM of 3e+24 panels", "use a larger --panel"]),
])
def test_rao_refuses_a_bem_it_cannot_afford_before_starting(args, words, tmp_path):
    res = runner.invoke(app, RAO + args + ["--out", str(tmp_path / "o")])
    one_line_exit_2(res, *words)
    assert not (tmp_path / "o").exists()


def test_the_bem_budget_is_memory_and_time():
    hull = dict(shape="box", length_m=100, beam_m=20, draught_m=5, frequencies=33, headings=1)
    # (100, 20, 10): bottom 2000, sides 2 (100 + 20) 5: 3200 panels, 300 MB + 64 x 3200^2 B
    with pytest.raises(ScenarioError, match=r"3,200 panels .* about 955 MB in memory \(this machine: 1 GiB"):
        check_bem_size(panel_m=1.0, memory_bytes=GIB, **hull)
    with pytest.raises(ScenarioError, match="would take about"):
        check_bem_size(panel_m=1.0, memory_bytes=64 * GIB, max_seconds=60, **hull)
    assert check_bem_size(panel_m=1.0, memory_bytes=64 * GIB, max_seconds=MAX_BEM_S, **hull).panels == 3200


@pytest.mark.parametrize("args, words", [
    (["--headings", "inf"], ["--headings inf: expected finite headings"]),
    (["--headings", "nan,90"], ["--headings nan,90: expected finite headings"]),
    (["--headings", "x"], ["--headings x: expected numbers"]),
    (["--omega", "0.2:1.8:99999999999999"], ["--omega 0.2:1.8:99999999999999: expected first:last:count",
                                            "count <= 2000"]),
    (["--omega", "0.2:inf:10"], ["--omega 0.2:inf:10: expected"]),
    (["--omega", "0.2:1.8:1"], ["--omega 0.2:1.8:1: expected"]),
    (["--omega", "1:2"], ["--omega 1:2: expected first:last:count"]),
    (["--roll-damping", "1e308"], ["--roll-damping 1e+308: expected a fraction of critical damping from 0 to 1"]),
])
def test_rao_bad_values_are_one_line(args, words, tmp_path):
    one_line_exit_2(runner.invoke(app, RAO + args + ["--out", str(tmp_path / "o")]), *words)


def test_hull_bem_refuses_non_finite_headings_itself():
    pytest.importorskip("capytaine")
    import numpy as np

    from marinecdpr.motion.bem import hull_bem

    with pytest.raises(ValueError, match="heading_deg must be finite"):
        hull_bem(length_m=100, beam_m=20, draught_m=5, gm_m=2, roll_damping_ratio=0.05, omega=np.array([0.5, 1.0]),
                 heading_deg=np.array([np.nan]))


# ------------------------------------------------------------------ latency --calls
@pytest.mark.parametrize("calls, words", [
    ("1000000000", "--calls 1,000,000,000: more than the 10,000,000 calls"),
    ("1000000000000", "--calls 1e+12: more than the 10,000,000 calls"),
    ("9223372036854775807", "--calls 9.22e+18: more than"),
    ("1" * 31, "--calls 1.11e+30: more than"),
    ("1" * 400, "--calls 1e+399: more than"),
    ("0", "--calls 0: expected at least 1 call"),
    ("-3", "--calls -3: expected at least 1 call"),
])
def test_latency_refuses_counts_it_cannot_afford(calls, words):
    one_line_exit_2(runner.invoke(app, ["latency", "--calls", calls]), words)


def test_the_latency_budget_is_memory_too():
    check_latency_calls(MAX_LATENCY_CALLS, memory_bytes=8 * GIB)
    with pytest.raises(ScenarioError, match=r"--calls 10,000,000: timing them would need about 540 MB"):
        check_latency_calls(MAX_LATENCY_CALLS, memory_bytes=GIB // 2)


def test_sizes_beyond_yottabytes_read_as_numbers():
    assert human_bytes(5.76e50) == "5.76e+26 YB"
    assert human_bytes(2.4e12) == "2.4 TB"


# ------------------------------------------------------------------ the sea-state and control studies
def test_control_study_refuses_billions_of_steps_before_its_first_run(tmp_path):
    latencies = ",".join(["1"] * 1000)
    res = runner.invoke(app, ["control-study", "--latencies", latencies, "--duration", "1000", "--out",
                              str(tmp_path / "o")])
    one_line_exit_2(res, "--duration 1000 (6000 runs): simulating 1,000,001 steps of 0.001 s over 1000 s is "
                          "6,000,006,000 steps in all, more than the 1,000,000,000 steps")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args, words", [
    (["--rate", "1e9"], "--rate 1e+09 / --latencies 0,10,20,50,100: must be above 0.1 and at most 100000 Hz"),
    (["--latencies", "0,9000"], "--latencies 0,9000: must be between 0 and 5 s"),
])
def test_control_study_checks_the_mru_settings_before_its_first_run(args, words, tmp_path):
    one_line_exit_2(runner.invoke(app, ["control-study", *args, "--out", str(tmp_path / "o")]), words)


def test_clean_over_sea_states_refuses_billions_of_steps(tmp_path):
    headings = ",".join(str(h) for h in range(360))
    res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--serial", "--headings", headings, "--out",
                              str(tmp_path / "o")])
    line = one_line_exit_2(res, "paper_clean: ", "judging ", "sea states and poses", "more than the "
                            "1,000,000,000 steps a run can finish in sane time")
    assert math.isfinite(len(line)) and not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", [["operability"], ["clean", "--seas"]])
def test_sea_studies_refuse_more_workers_than_the_machine_can_run(command, tmp_path, monkeypatch):
    import os

    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    for workers in ("100", "1000000000"):
        res = runner.invoke(app, command + ["--workers", workers, "--out", str(tmp_path / "o")])
        one_line_exit_2(res, f"--workers {workers}: more than 4 per core of this machine's 2 gains nothing",
                         "use at most 8")


def test_each_worker_counts_its_own_process():
    from marinecdpr.planning.budget import BASE_BYTES, check_run_size, estimate_run
    from marinecdpr.scenario.loading import load_scenario

    sc = load_scenario("paper_sea")
    one, eight = (estimate_run(sc, "operability", cells=10, workers=w) for w in (1, 8))
    assert eight.memory_bytes - one.memory_bytes >= 7 * BASE_BYTES
    with pytest.raises(ScenarioError, match="judging on 8 workers at once would need about .*; use fewer workers"):
        check_run_size(sc, "operability", cells=10, workers=8, memory_bytes=(one.memory_bytes + 10**8) * 4 // 3)
