"""What a design study reports (issue 37, items 4, 13 and 14): each finalist's expected hours
in parts (cleaning, turns, moves, waiting for weather) and its binding constraints in
report.html, finalists.csv, summary.json and the command's output; a page that says whether
the finalists were flown; the cost objective with its unit; figures with plain-number log
axes, whole generations, the infeasible candidates drawn, a front without a trade-off
called so, and a legend for the finalists' drawing; "1 candidate", not "1 candidates"."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("pymoo")

import marinecdpr  # noqa: E402
from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.studies.design import (  # noqa: E402
    DesignStudy, Evaluation, Verification, baseline, candidate_scenario, load_design, study_cells,
)
from conftest import one_candidate_study, tiny_study_folder  # noqa: E402
from marinecdpr.studies.surface import surface_job  # noqa: E402

runner = CliRunner()
HERE = Path(__file__).parents[1] / "studies"
SMALL = re.search(r'SMALL = """(.*?)"""', (HERE / "test_design.py").read_text(), re.S).group(1)
# the small study with prices: the medium winch 4 000, the light rope 3 a metre, in EUR
PRICED = (SMALL.replace('name = "medium"\n', 'name = "medium"\ncost = 4000.0\n')
          .replace('name = "light"\n', 'name = "light"\ncost_per_m = 3.0\n'))


def _study_file(folder: Path, text: str) -> Path:
    (folder / "seas.csv").write_text("hs_m,tp_s,probability\n1.0,8.0,0.6\n5.0,10.0,0.4\n")
    path = folder / "study.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def priced(tmp_path_factory):
    """The small study's medium winch and light rope on its 6 x 3 m frame, judged, as a
    one-candidate study: on paper_clean's top 3 m of side over 10 m amidships (heights 8.6 to
    11.6 m, stations -5 to 5 m; four placements, the template's baseline judged in a fraction
    of the whole side's time), where, as over the whole side, the screen passes the Hs 1 m sea
    state and not the 5 m one (share 0.6, the least slack, then the sag's)."""
    import tomli_w

    from marinecdpr.scenario.importing.common import toml_plain

    folder = tmp_path_factory.mktemp("priced")
    band = toml_plain(marinecdpr.load_scenario("paper_clean").model_dump(exclude_none=True))
    band["cleaning"]["surface"].update(stations_m=[-5.0, 5.0], heights_m=[8.6, 11.6])
    (folder / "band.toml").write_text(tomli_w.dumps(band))
    path = _study_file(folder, PRICED.replace('scenario = "paper_clean"', 'scenario = "band.toml"'))
    spec, template = load_design(path)
    spec = spec.model_copy(update={"finalists": 1})
    cells = study_cells(spec, path.parent)
    study = one_candidate_study(spec, template, cells)
    return spec, template, study


def test_the_hours_in_parts_are_the_paths_lanes_steps_and_moves_by_hand(priced):
    """Cleaning + turns is each placement's coverage path; the turns are its steps between
    lanes, each a rest-to-rest move of one lane spacing under the tool's speed, acceleration
    and jerk (timed here by the S-curve's closed form); the moves are (n - 1) x 300 s; the
    weather is the rest of the expected hours: surface hours (1 / share - 1)."""
    from marinecdpr.motion.trajectory import cleaning_path
    from marinecdpr.scenario.cleaning import Cleaning

    spec, template, study = priced
    e = study.evaluations[0]
    sc = candidate_scenario(spec, template, e.x)
    job = surface_job(sc, move_time_s=300.0, digits=2)
    c = sc.cleaning

    def rest_to_rest(d, v, a, j):  # the jerk-limited move's time, s
        tv = v / a + a / j if v * j >= a * a else 2 * np.sqrt(v / j)
        if d >= v * tv:
            return d / v + tv
        if d >= 2 * a**3 / j**2:
            vp = (-a * a / j + np.sqrt(a**4 / j**2 + 4 * a * d)) / 2
            return 2 * (vp / a + a / j)
        return 4 * (d / (2 * j)) ** (1 / 3)

    turns = 0.0
    for p in job.placements:
        u, w = (max(round(s, 2), 1e-3) for s in p.extent_m)
        data = c.model_dump(exclude_none=True) | {"panel_m": [[0, 0], [u, 0], [u, w], [0, w]], "holes_m": []}
        data.pop("surface")
        path = cleaning_path(Cleaning.model_validate(data))
        steps = ~(path.lane_segment | path.boundary_segment)
        assert steps.sum() == path.lanes - 1
        turns += (path.lanes - 1) * rest_to_rest(path.spacing_m, c.speed_m_s, c.acceleration_m_s2, c.jerk_m_s3)
    h = e.hours_breakdown()
    assert h["turns"] * 3600.0 == pytest.approx(turns, rel=1e-9) and turns > 0
    assert (h["cleaning"] + h["turns"]) * 3600.0 == pytest.approx(job.job_s.sum(), rel=1e-12)
    assert h["moves"] * 3600.0 == (len(job.placements) - 1) * 300.0
    assert h["weather"] == pytest.approx(e.surface_hours * (1.0 / e.sea_share - 1.0), rel=1e-12)
    assert sum(h.values()) == pytest.approx(e.expected_hours, rel=1e-12)


def test_the_binding_constraints_are_the_margins_nearest_their_limit(priced):
    """Slack = margin / what it is taken from: sea share (0.6 - 0.5) / 0.6, sag
    (0.05 - 0.2 x 6.708^2 / 400) / 0.05, the winch's power (1 500 - 1 333.3 x 0.2) / 1 500
    ...; the two least are reported."""
    spec, template, study = priced
    e = study.evaluations[0]
    span = np.hypot(6.0, 3.0)
    assert e.sea_share == 0.6
    assert e.slack["sea_share"] == pytest.approx(0.1 / 0.6, rel=1e-12)
    assert e.slack["sag_m"] == pytest.approx((0.05 - 0.2 * span**2 / 400.0) / 0.05, rel=1e-12)
    assert e.slack["winch_power_W"] == pytest.approx((1500.0 - 100 / 0.075 * 0.2) / 1500.0, rel=1e-12)
    assert e.slack["winch_speed_m_s"] == pytest.approx((13 * 0.075 - 0.2) / (13 * 0.075), rel=1e-12)
    least = sorted(e.slack.items(), key=lambda kv: kv[1])[:2]
    assert e.binding() == least and [k for k, _ in least] == ["sea_share", "sag_m"]


def test_the_report_says_the_hours_in_parts_and_what_binds_and_not_that_it_flew(priced, tmp_path):
    """--no-verify: the page says the finalists were not flown; the cost objective's column is
    a cost with its unit (4 x (4 000 + 3 x 6.708) = 16 080.5 EUR by hand); finalists.csv and
    summary.json give the hours in parts, summing to the expected hours."""
    from marinecdpr.report.design import write_design

    spec, template, study = priced
    spec = spec.model_copy(update={"objective": "cost", "cost_unit": "EUR"})
    study = DesignStudy(spec=spec, evaluations=study.evaluations, generation=study.generation, front=study.front,
                        baseline=study.baseline)
    e = study.evaluations[0]
    write_design(study, template, tmp_path)
    page = (tmp_path / "report.html").read_text()
    assert "flown through the cleaning job in every sea state" not in page
    assert "The finalists were not flown in the time domain" in page
    assert "<th>cost of 4 winches and 4 ropes (EUR)</th>" in page and "<th>kW</th>" not in page
    cost = 4 * (4000.0 + 3.0 * np.hypot(6.0, 3.0))
    assert e.cost == pytest.approx(cost, rel=1e-12)
    assert f"<td>{cost:.6g}</td>" in page
    h = e.hours_breakdown()
    assert (f"{h['cleaning']:.3g} cleaning + {h['turns']:.3g} turns between lanes + {h['moves']:.3g} moving the "
            f"frame + {h['weather']:.3g} waiting for weather") in page
    assert f"sea_share ({100 * e.slack['sea_share']:.3g} % left), sag_m" in page
    top = max(h, key=h.get)
    assert f"What limits the best design: of its {e.expected_hours:.4g} expected h" in page
    assert {"moves": "moving the frame", "weather": "waiting for weather"}.get(top, top) in page.split(
        "What limits the best design")[1][:200]
    (row,) = list(csv.DictReader(open(tmp_path / "finalists.csv")))
    parts = [float(row[k]) for k in ("cleaning_hours", "turn_hours", "move_hours", "weather_hours")]
    assert sum(parts) == pytest.approx(float(row["expected_hours"]), rel=1e-9)
    assert row["binding_1"] == "sea_share" and row["td_share"] == ""
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["verified"] is False and s["objective_label"] == "cost of 4 winches and 4 ropes (EUR)"
    assert sum(s["best"]["hours"].values()) == pytest.approx(s["best"]["expected_hours"], rel=1e-12)
    assert s["best"]["binding"][0]["constraint"] == "sea_share"
    # flown: the page says so, as built, and gives the time domain's hours
    v = Verification(index=0, rank=1, surface_hours=e.surface_hours, screen_share=0.6, td_share=1.0,
                     screen_expected_hours=e.expected_hours, td_expected_hours=e.surface_hours, agree=1,
                     screen_works_td_fails=0, screen_fails_td_works=1, reasons=[], plant="own")
    (tmp_path / "flown").mkdir()
    write_design(study, template, tmp_path / "flown", [v])
    page = (tmp_path / "flown" / "report.html").read_text()
    assert "were also flown as built" in page and "not flown" not in page
    (row,) = list(csv.DictReader(open(tmp_path / "flown" / "finalists.csv")))
    assert float(row["td_weather_hours"]) == 0.0 and row["plant"] == "own"


def _ev(power, hours, feasible=True, share=0.9):
    return Evaluation(x={}, feasible=feasible, reason="", placements=1, surface_hours=hours * share,
                      sea_share=share, expected_hours=hours, power_kW=power, cost=power * 1000.0,
                      tension_max_N=1.0, mass_kg=1.0)


def _toy(spec, evaluations, generation, front):
    return DesignStudy(spec=spec, evaluations=evaluations, generation=np.array(generation), front=front,
                       baseline=evaluations[0])


def _labels(ax):
    """The hours axis's visible tick labels."""
    ax.figure.canvas.draw()
    lo, hi = ax.get_ylim()
    out = []
    for tick in ax.yaxis.get_major_ticks() + ax.yaxis.get_minor_ticks():
        if lo <= tick.get_loc() <= hi and tick.label1.get_visible() and tick.label1.get_text():
            out.append(tick.label1.get_text())
    return out


def test_the_pareto_figure_draws_every_candidate_on_plain_axes(priced):
    """Five candidates: two feasible, one short of a constraint (at its hours), one that works
    in no sea state (no hours: drawn along the top): all five drawn; the hours axis labelled
    40, 50, ..., not 4x10^1; the power axis from zero; a front whose two designs differ by
    0.2 % in hours and 0.5 % in power said to be no trade-off."""
    from marinecdpr.report.design import pareto_figure

    spec = priced[0]
    evs = [_ev(20.0, 40.0), _ev(20.1, 39.92), _ev(6.0, 55.0, feasible=False),
           _ev(1.6, float("inf"), feasible=False, share=0.0), _ev(8.0, 45.0)]
    fig = pareto_figure(_toy(spec, evs, [0, 0, 0, 1, 1], [1, 0]))
    ax = fig.axes[0]
    drawn = sum(len(c.get_offsets()) for c in ax.collections)
    assert drawn == 5
    labels = _labels(ax)
    assert labels and all(re.fullmatch(r"\d+(\.\d+)?", t) for t in labels), labels
    assert ax.get_xlim()[0] == 0.0
    assert "no trade-off" in ax.get_title() and "0.2 % in hours" in ax.get_title()
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(t.startswith("infeasible: no hours") for t in legend)
    assert any(t.startswith("infeasible: a constraint not met") for t in legend)
    cost = pareto_figure(_toy(spec.model_copy(update={"objective": "cost", "cost_unit": "EUR"}), evs,
                              [0, 0, 0, 1, 1], [1, 0]))
    assert cost.axes[0].get_xlabel() == "cost of 4 winches and 4 ropes (EUR)"


@pytest.mark.parametrize("generations", [1, 3])
def test_the_convergence_figure_counts_whole_generations(priced, generations):
    from marinecdpr.report.design import convergence_figure

    spec = priced[0]
    evs = [_ev(20.0, 40.0 + k) for k in range(2 * generations)]
    fig = convergence_figure(_toy(spec, evs, np.repeat(np.arange(generations), 2), [0]))
    ax = fig.axes[0]
    fig.canvas.draw()
    lo, hi = ax.get_xlim()
    ticks = [t for t in ax.get_xticks() if lo <= t <= hi]
    assert ticks and all(t == round(t) for t in ticks), ticks
    assert all(re.fullmatch(r"\d+(\.\d+)?", t) for t in _labels(ax))


def test_the_finalists_drawing_has_a_legend(priced):
    from marinecdpr.report.design import finalists_figure

    spec, template, study = priced
    fig = finalists_figure(study, template)
    texts = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert "platform at the panel's four corners" in texts and "frame and its anchors" in texts


def test_an_interrupted_search_counts_one_candidate_as_one(tmp_path, monkeypatch):
    """Ctrl-C after one candidate: "1 candidate kept", not "1 candidates"."""
    import marinecdpr.studies.design as design

    def cut(spec, template, cells, *, journal=None, **kw):
        journal.write_text('{"study": "k"}\n{"x": {}}\n')
        raise KeyboardInterrupt

    monkeypatch.setattr(design, "search", cut)
    path = _study_file(tmp_path, SMALL)
    res = runner.invoke(app, ["design", str(path), "--out", str(tmp_path / "o"), "--no-verify"])
    assert res.exit_code == 130
    assert f"interrupted; 1 candidate kept in {tmp_path / 'o' / 'journal.jsonl'}" in res.output.replace("\n", "")


def test_the_command_prints_the_best_design_s_hours_in_parts(tmp_path):
    """One generation of four: the line after the best design's gives its hours in parts,
    as summary.json has them, summing to its expected hours; the page says nothing was flown.
    (The small study on paper_clean's 10 x 3 m midship band: the command's words on any surface.)"""
    path = tiny_study_folder(tmp_path, SMALL.replace('scenario = "paper_clean"', 'scenario = "template.toml"'),
                             "hs_m,tp_s,probability\n1.0,8.0,0.6\n5.0,10.0,0.4\n")
    out = tmp_path / "o"
    res = runner.invoke(app, ["design", str(path), "--out", str(out), "--population", "4", "--generations", "1",
                              "--no-verify"])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    h = s["best"]["hours"]
    line = (f"its {s['best']['expected_hours']:.4g} expected h: {h['cleaning']:.3g} h cleaning + {h['turns']:.3g} h "
            f"turns between lanes + {h['moves']:.3g} h moving the frame + {h['weather']:.3g} h waiting for weather; "
            f"binding: {s['best']['binding'][0]['constraint']}")
    assert line in res.stdout
    assert sum(h.values()) == pytest.approx(s["best"]["expected_hours"], rel=1e-12)
    assert f"small: {s['candidates']} candidates" in res.stdout and "over 2 sea states" in res.stdout
    assert "not flown" in (out / "report.html").read_text()
