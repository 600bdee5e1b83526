"""Issue 21, items 9, 10 and 12 (figures): the reports' words and figures say what they show.

The figures are checked on their matplotlib artists: legend entries drawn as their lines,
legends inside the saved figure, axis formatters without an offset, the numbers in cells.
"""

import re
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_rgba

import marinecdpr
import marinecdpr.report.cleaning as cleaning_report
import marinecdpr.report.figures as figures
from marinecdpr.report.figures import FIGURE_DPI, RUN_TITLES
from marinecdpr.report.text import findings, write_report_html

sys.path.insert(0, str(Path(__file__).parent))
from test_figures import _long_runs  # noqa: E402  (made-up runs: the figures without simulating)


def _within_figure(fig, artist, tmp_path):
    """The artist's box lies inside the figure once saved as the reports save it."""
    fig.savefig(tmp_path / "saved.png", dpi=FIGURE_DPI)
    box = artist.get_window_extent(fig.canvas.get_renderer())
    return box.x0 >= 0 and box.y0 >= 0 and box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height


def _legend_entries(fig):
    legend = fig.legends[0] if fig.legends else fig.axes[0].get_legend()
    return {t.get_text(): h for t, h in zip(legend.get_texts(), legend.legend_handles)}


# ------------------------------------------------------------------ item 9
@pytest.mark.parametrize("figure", ["cable_lengths", "tracking"])
def test_every_run_is_drawn_as_its_legend_entry_in_both_columns(figure, paper, captured_figures, tmp_path):
    """The closed loop's entry was dashed, its lines solid (a dashed line through a
    decimated zigzag shows solid; the error column was always solid)."""
    runs = _long_runs(paper)
    getattr(figures, f"plot_{figure}")(runs, paper, tmp_path / f"{figure}.png")
    fig = captured_figures[f"{figure}.png"]
    entries = _legend_entries(fig)
    for name in runs:
        handle = entries[RUN_TITLES[name]]
        colour = to_rgba(handle.get_color())
        drawn = [ln for ax in fig.axes for ln in ax.get_lines() if to_rgba(ln.get_color()) == colour]
        assert len(drawn) == len(fig.axes)  # one line per axes, lengths and errors
        for ln in drawn:
            assert ln.get_linestyle() == handle.get_linestyle(), (name, ln.get_linestyle())
            assert ln.get_linewidth() == handle.get_linewidth()


def test_the_path_figures_legend_is_inside_the_figure(paper, captured_figures, tmp_path):
    figures.plot_path(_long_runs(paper), paper, tmp_path / "path.png")
    fig = captured_figures["path.png"]
    assert len(fig.legends) == 1 and len(fig.legends[0].get_texts()) == 6
    assert _within_figure(fig, fig.legends[0], tmp_path)


def _summary(fixed_m, moving_m=1.5e-7, bound_m=0.019):
    run = dict(max_abs_error_x_m=moving_m, max_abs_error_z_m=moving_m, max_abs_cable_length_error_m=[moving_m] * 4,
               max_abs_error_theta_deg=1e-6, within_error_bound=True, beyond_error_bound=[],
               tension_limit_excess_N=0.0, controller_fallbacks=0)
    fixed = dict(run, max_abs_error_x_m=fixed_m, within_error_bound=fixed_m <= bound_m,
                 beyond_error_bound=[] if fixed_m <= bound_m else ["x"])
    return {"error_bound_m": bound_m, "error_bound_deg": 1.0, "steps": 100, "open_loop": run,
            "closed_loop": dict(run), "fixed_base_open_loop": fixed}


def test_the_fixed_base_plan_is_measured_against_the_error_bound(paper):
    """Not against the moving-base plan's open-loop residual (the hold of the tensions over a
    step with ideal cables): "219 000 times the moving-base plan's 153 nm" meant nothing."""
    text = " ".join(findings(_summary(0.0335), paper))
    assert "errs by 33.5 mm, 1.76 times the error bound of 19 mm" in text
    assert "times the moving-base plan" not in text and "223 000" not in text
    text = " ".join(findings(_summary(0.0095), paper))
    assert "errs by 9.5 mm, 50 % of the error bound of 19 mm" in text


@pytest.fixture(scope="module")
def short_vp():
    sc = marinecdpr.load_scenario("paper")
    return marinecdpr.virtual_prototype(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 0.3}))


def test_the_report_numbers_its_figures_in_page_order_and_names_the_papers(short_vp, tmp_path):
    from marinecdpr.report.writers import write_virtual_prototype

    write_virtual_prototype(short_vp, tmp_path)
    page = (tmp_path / "report.html").read_text()
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", page)
    assert [c.split(":")[0] for c in captions] == ["Figure 1", "Figure 2", "Figure 3", "Figure 4"]
    assert "like the paper&#x27;s figure 5" in captions[0] and "like the paper&#x27;s figure 7" in captions[2]
    # paper builds nothing beyond point anchors: no table of dashes
    assert "Cables as built" not in page


def test_the_cables_as_built_table_shows_where_something_is_built(short_vp, tmp_path):
    summary = dict(short_vp.summary)
    assert all(e["length_change_m"] is None and e["tension_change_N"] is None
               for e in summary.get("error_budget", {}).values())
    summary["error_budget"] = dict(summary.get("error_budget", {}))
    summary["error_budget"]["pulleys"] = {"length_change_m": 0.0012, "tension_change_N": 3.4,
                                          "workspace_change": None, "note": "the pulleys' wrap"}
    path = write_report_html(summary, short_vp.scenario, {}, tmp_path / "report.html")
    page = path.read_text()
    assert "Cables as built" in page and "1.2 mm" in page


# ------------------------------------------------------------------ item 10
@pytest.fixture(scope="module")
def short_clean(tmp_path_factory):
    from marinecdpr.studies.cleaning import cleaning_job, ship_side

    sc = marinecdpr.load_scenario("paper_clean")
    job = cleaning_job(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 2.0}))
    job.summary["hull"] = ship_side(job.summary, hull_area_m2=100.0, move_time_s=600.0)
    return job


def test_the_cleaning_report_names_its_figures_in_words_and_units(short_clean, tmp_path):
    out = cleaning_report.write_cleaning(short_clean, tmp_path)
    page = (tmp_path / "report.html").read_text()
    job = page[page.index("<h2>The job</h2>"):page.index("<ul>")]
    rows = dict(re.findall(r"<tr><th>(.*?)</th><td>(.*?)</td></tr>", job))
    assert not any(re.search(r"_(pct|m|N|s|kJ|m2|m2_h)$", k) for k in rows), rows  # no JSON keys
    s = short_clean.summary
    assert rows["panel cleaned"] == f"{s['coverage_pct']:.2f} %"
    p95 = rows["cross-track error, 95th percentile"]
    value, unit = p95.split()
    assert unit in ("mm", "µm", "nm") and 1.0 <= float(value) < 1000.0
    scale = {"mm": 1e-3, "µm": 1e-6, "nm": 1e-9}[unit]
    assert float(value) * scale == pytest.approx(s["p95_cross_track_error_m"], rel=5e-3)
    assert rows["hull: time"] == f"{s['hull']['hours']:.1f} h"  # the hull estimate in the table
    assert "252 placements" in rows["hull"] or f"{s['hull']['placements']} placements" in rows["hull"]
    assert "1.2 m, 12.9 s" in page  # the pass along the edges, and what it costs
    assert len(out) == 5


def test_the_cleaning_series_show_the_tension_limits_and_a_colour_per_line(short_clean, tmp_path, monkeypatch):
    figs = {}
    monkeypatch.setattr(cleaning_report, "_save", lambda fig, path, dpi=None: figs.setdefault(Path(path).name, fig))
    cleaning_report.plot_cleaning_series(short_clean, tmp_path / "cleaning.png")
    fig = figs["cleaning.png"]
    tensions, _, tracking = fig.axes
    levels = {float(ln.get_ydata()[0]) for ln in tensions.get_lines() if ln.get_linestyle() == "--"}
    robot = short_clean.scenario.robot
    assert levels == {float(robot.tension_min.min()), float(robot.tension_max.max())}
    cables = {to_rgba(ln.get_color()) for ln in tensions.get_lines() if ln.get_label().startswith("cable")}
    (error,) = tracking.get_lines()
    assert to_rgba(error.get_color()) not in cables
    entries = _legend_entries(fig)
    assert "tension limits" in entries


def test_operability_cells_print_the_probability_of_success(paper, captured_figures, tmp_path):
    """Each cell printed its probability of occurrence over a colour bar of the probability
    of success; the number now is the colour's."""
    op = SimpleNamespace(
        headings_deg=(180.0,), margin_N=0.0, per_heading={180.0: 0.5}, per_heading_interval=None,
        results=[SimpleNamespace(realisations=10)],
        scatter=SimpleNamespace(hs=np.array([1.0, 3.0]), tp=np.array([6.0, 8.0]),
                                probability=np.array([[0.4, 0.3], [0.2, 0.1]])),
        probability_grid=lambda h: np.array([[1.0, 0.7], [0.0, np.nan]]))
    op.scatter.probability[1, 1] = 0.0
    figures.plot_operability(op, paper, tmp_path / "operability.png")
    fig = captured_figures["operability.png"]
    cells = {(round(t.get_position()[0]), round(t.get_position()[1])): t.get_text() for t in fig.axes[0].texts}
    assert cells == {(0, 0): "100", (1, 0): "70", (0, 1): "0"}
    assert "numbers: probability of success" in fig.get_suptitle()


def test_control_study_headroom_axis_reads_plainly_and_coinciding_curves_all_show(tmp_path, captured_figures):
    runs = [SimpleNamespace(prediction=p, pose_from=src, latency_s=lat, rms_error_m=1e-6 * (1 + lat),
                            headroom_N=128.7812 + 1e-4 * lat)
            for p in ("none", "kinematic", "ar") for src in ("sensor", "encoders") for lat in (0.0, 0.02, 0.05)]
    study = SimpleNamespace(runs=runs, scenario="paper_sea", settle_s=11.0, rate_hz=100.0)
    h = np.array([0.1, 1.0])
    err = np.ones((2, 3, 6))
    prediction = SimpleNamespace(horizons_s=h, predictor=err, taylor=err, hold=2 * err)
    import marinecdpr.studies.control as control
    control_moving = control.moving_dofs
    try:
        control.moving_dofs = lambda p: np.ones(6, dtype=bool)
        figures.plot_control_study(study, prediction, tmp_path / "control_study.png")
    finally:
        control.moving_dofs = control_moving
    fig = captured_figures["control_study.png"]
    fig.savefig(tmp_path / "saved.png", dpi=FIGURE_DPI)
    headroom = fig.axes[1]
    assert headroom.yaxis.get_offset_text().get_text() == ""
    ticks = [t for t in headroom.get_yticks() if headroom.get_ylim()[0] <= t <= headroom.get_ylim()[1]]
    assert min(np.diff(ticks)) >= 0.1  # not 0.0004 N
    labels = [t.get_text() for t in headroom.get_yticklabels()]
    assert all("e" not in lab for lab in labels) and any(lab.startswith("128") for lab in labels)
    # curves on the same points: each drawn wider or with larger markers than those on top of it
    for ax in (fig.axes[1], fig.axes[2]):
        lines = ax.get_lines()
        same = [ln for ln in lines if np.allclose(ln.get_ydata(), lines[0].get_ydata())]
        assert len(same) >= 2
        sizes = [(ln.get_linewidth(), ln.get_markersize()) for ln in same]
        assert all(a[0] > b[0] or a[1] > b[1] for a, b in zip(sizes, sizes[1:])), sizes


# ------------------------------------------------------------------ item 12 (figure)
def test_the_windows_shades_are_in_the_legend(captured_figures, tmp_path):
    from marinecdpr.studies.weather import SeaStateSeries, weather_windows

    t = np.arange(48.0)
    hs = np.where((t % 24) < 14, 1.0, 3.0)
    hs[30:34] = 3.0
    series = SeaStateSeries(t_h=t, hs_m=hs, tp_s=np.full(48, 8.0))
    w = weather_windows(series, duration_h=12.0, alpha=1.0, hs_limit_m=2.0)
    figures.plot_windows(series, w, tmp_path / "windows.png", title="t")
    labels = [t.get_text() for t in captured_figures["windows.png"].axes[0].get_legend().get_texts()]
    assert "window of at least 12 h (the operation fits)" in labels
    assert "window shorter than 12 h" in labels
