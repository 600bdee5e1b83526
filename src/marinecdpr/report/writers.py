"""Each command's files, composed from the CSVs, figures and page of the modules below:
``plan.csv`` and ``tensions.png`` (plan), the main job's folder (simulate), the workspace
and operability maps."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, NamedTuple

import numpy as np

from marinecdpr.planning.planner import Plan
from marinecdpr.report.figures import (
    TensionEnvelope,
    _pose_names,
    _pyplot,
    plot_cable_lengths,
    plot_operability,
    plot_path,
    plot_tension_envelope,
    plot_tensions,
    plot_tracking,
    plot_workspace,
)
from marinecdpr.forked import Forked
from marinecdpr.report.files import _row_format, _write_csv, _write_rows, atomic_path, write_json
from marinecdpr.report.text import write_report_html
from marinecdpr.scenario.schema import Scenario

__all__ = [
    "plan_columns",
    "write_plan_csv",
    "plan_csv_writer",
    "write_plan_stream",
    "write_sim_csv",
    "write_virtual_prototype",
    "write_workspace",
    "write_operability",
    "operability_summary",
    "write_rao",
    "write_windows",
    "windows_summary",
]


def plan_columns(plan: Plan, scenario: Scenario) -> tuple[list[str], np.ndarray]:
    """Column names and values of ``plan.csv``.

    Columns: ``t`` (s); the controlled pose in C (``x``, ``z``, ``theta_y`` for a
    planar robot, ``x, y, z, rx, ry, rz`` for a spatial one; m and deg);
    ``L1..Ln`` (cable lengths, m); ``Tpinv1..Tpinvn`` (eq. 18 tensions, N);
    ``T1..Tn`` (the method's tensions, N; empty where infeasible); with winches
    (``robot.winch``) ``Tlo1..Tlon``, ``Thi1..Thin`` (the tensions each winch can give at that
    step, N); with heavy cables (``robot.cable_weight_N_m``) ``sag1..sagn`` (the extra length
    paid out for the sag, m) and ``Twinch1..Twinchn`` (the tension at the winch, N); with
    ``robot.clearance_m``, ``gap1..gapn`` (each cable's least distance to another cable, the
    platform's body or an obstacle, m: :attr:`Plan.clearance`);
    ``feasible`` (1/0).

    Returns
    -------
    names : list of str
    values : ndarray, shape (n_steps, n_columns)
    """
    pose_names, dofs = _pose_names(scenario)
    pose = _pose_columns(plan.pose, dofs)
    n = scenario.robot.n_cables
    names = (
        ["t"] + pose_names + [f"L{i}" for i in range(1, n + 1)]
        + [f"Tpinv{i}" for i in range(1, n + 1)] + [f"T{i}" for i in range(1, n + 1)]
    )
    columns = [plan.t, pose, plan.lengths, plan.tensions_pinv, plan.tensions]
    winch, sag = plan.winch, plan.sag
    for prefix, values in (("Tlo", winch and winch.lower), ("Thi", winch and winch.upper),
                           ("sag", sag and sag.lengths), ("Twinch", sag and sag.winch_tensions),
                           ("gap", plan.clearance)):
        if values is not None:
            names += [f"{prefix}{i}" for i in range(1, n + 1)]
            columns.append(values)
    return names + ["feasible"], np.column_stack(columns + [plan.feasible.astype(float)])


def _pose_columns(pose: np.ndarray, dofs: list[int]) -> np.ndarray:
    """The pose's controlled columns, angles in degrees."""
    out = pose[:, dofs].copy()
    for col, i in enumerate(dofs):
        if i >= 3:
            out[:, col] = np.degrees(out[:, col])
    return out


def write_plan_csv(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Write :func:`plan_columns` as CSV (NaN written as an empty field)."""
    names, values = plan_columns(plan, scenario)
    return _write_csv(names, values, path)


# ------------------------------------------------------------ plans made in chunks
@contextmanager
def plan_csv_writer(scenario: Scenario, path: Path) -> Iterator:
    """``plan.csv`` written piece by piece: yields ``write(piece)``, to call with each piece
    of a plan (:func:`~marinecdpr.iter_plan`) in order, at least one.

    The file is byte for byte what :func:`write_plan_csv` writes for the whole plan, and
    appears (atomically) only when the block ends without an error; memory holds one
    piece's text at a time.
    """
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        rows = [0]

        def write(piece: Plan) -> None:
            names, values = plan_columns(piece, scenario)
            if len(values) == 0:
                return
            if rows[0] == 0:
                fh.write(",".join(names) + "\n")
            _write_rows(fh, _row_format(len(names), int_last=True), values)
            rows[0] += len(values)

        yield write
        if rows[0] == 0:
            raise ValueError("plan_csv_writer: no piece of a plan was written")


def write_plan_stream(pieces, scenario: Scenario, csv_path: Path, figure_path: Path | None):
    """``plan.csv`` and ``tensions.png`` from a plan made in pieces (:func:`~marinecdpr.iter_plan`),
    holding one piece at a time.

    Parameters
    ----------
    pieces : iterable of Plan
        The scenario's whole plan, in order.
    scenario : Scenario
    csv_path : Path
    figure_path : Path or None
        None: no figure drawn (the CSV the same).

    Returns
    -------
    marinecdpr.planning.planner.PlanSummary
        The plan's figures (steps, feasible steps, tension ranges, :meth:`infeasibility`),
        with ``planning_s``, the time spent making the pieces, s.
    """
    import time

    from marinecdpr.planning.planner import PlanSummary

    summary = PlanSummary()
    envelope = None if figure_path is None else TensionEnvelope(scenario.time.n_steps, scenario.robot.n_cables)
    summary.planning_s = 0.0
    it = iter(pieces)
    with plan_csv_writer(scenario, csv_path) as write:
        while True:
            t0 = time.perf_counter()
            piece = next(it, None)
            summary.planning_s += time.perf_counter() - t0
            if piece is None:
                break
            write(piece)
            if envelope is not None:
                envelope.add(piece)
            summary.add(piece)
            del piece
    if envelope is not None:
        plot_tension_envelope(envelope, scenario, figure_path)
    return summary


# ------------------------------------------------------------------ simulations
def write_sim_csv(res, scenario: Scenario, path: Path) -> Path:
    """``sim_<run>.csv``: t; planned and actual pose (``x_plan``.., ``x``..; m, deg);
    planned and actual cable lengths (``Lplan1``.., ``L1``..; m); applied and commanded
    tensions (``T1``.., ``Tcmd1``..; N)."""
    pose_names, dofs = _pose_names(scenario)
    n = scenario.robot.n_cables
    names = (["t"] + [f"{p}_plan" for p in pose_names] + pose_names
             + [f"Lplan{i}" for i in range(1, n + 1)] + [f"L{i}" for i in range(1, n + 1)]
             + [f"T{i}" for i in range(1, n + 1)] + [f"Tcmd{i}" for i in range(1, n + 1)])
    values = np.column_stack([
        res.t, _pose_columns(res.pose_planned, dofs), _pose_columns(res.pose, dofs),
        res.lengths_planned, res.lengths, res.tensions, res.tensions_commanded])
    return _write_csv(names, values, path, int_last=False)


def write_virtual_prototype(vp, folder: Path, *, figures: bool = True) -> list[Path]:
    """Every file of the main job in ``folder``: plan.csv, sim_<run>.csv, the figures,
    summary.json and report.html. Returns the paths written.

    Where it pays (:func:`~marinecdpr.forked.can_fork`), two of the figures are drawn by a
    forked copy of this process meanwhile; the files are the same either way. Without
    ``figures`` no figure is drawn (nor any process forked) and the report says so; the
    other files are the same.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    sc = vp.scenario
    apart = None
    if figures:
        # drawing the figures is most of the work: two of them (about half) are drawn in a
        # second process while this one writes the CSVs and draws the other two
        _pyplot()  # imported once, before the fork, for both
        apart = Forked(lambda: (plot_tensions(vp.plan, sc, folder / "tensions.png"),
                                 plot_cable_lengths(vp.results, sc, folder / "cable_lengths.png")))
    drawn = None  # the figures not drawn: the report says so
    try:
        paths = [write_plan_csv(vp.plan, sc, folder / "plan.csv")]
        for name, res in vp.results.items():
            paths.append(write_sim_csv(res, sc, folder / f"sim_{name}.csv"))
        if apart is not None:
            tracking = plot_tracking(vp.results, sc, folder / "tracking.png")
            path_figure = plot_path(vp.results, sc, folder / "path.png")
            tensions, lengths = apart.result()
            # numbered by their order on the page; the paper's figures they follow named in words
            drawn = {
                "Figure 1: cable tensions (a) from eq. (18) and (b) after optimisation, like the paper's figure 5":
                    tensions,
                "Figure 2: cable lengths, planned (kinematics) and actual (virtual prototype), like the paper's "
                "figure 6": lengths,
                "Figure 3: planned and actual pose, and the tracking errors, like the paper's figure 7": tracking,
                "Figure 4: the platform's path in C, planned and actual": path_figure,
            }
            paths += list(drawn.values())
    finally:
        if apart is not None:
            apart.stop()
    paths.append(write_json(vp.summary, folder / "summary.json"))
    paths.append(write_report_html(vp.figures, sc, drawn, folder / "report.html", plan=vp.plan))
    return paths


# ------------------------------------------------------------ workspace, operability
def write_workspace(ws, scenario: Scenario, folder: Path, *, figures: bool = True) -> list[Path]:
    """``workspace.csv`` (one row per grid pose; with ``robot.clearance_m`` also
    ``least_clearance_m`` and ``interference_free`` (1/0)) and, with ``figures``,
    ``workspace.png`` (the maps, :func:`plot_workspace`)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    U, V = np.meshgrid(ws.u, ws.v, indexing="ij")
    names = [f"{ws.axes[0]}_m", f"{ws.axes[1]}_m", "fraction_feasible", "min_margin_N",
             "pinv_fraction_feasible"]
    columns = [U.ravel(), V.ravel(), ws.fraction_feasible.ravel(), ws.min_margin_N.ravel(),
               ws.pinv_fraction_feasible.ravel()]
    if ws.least_clearance_m is not None:  # the interference layer
        names += ["least_clearance_m", "interference_free"]
        columns += [ws.least_clearance_m.ravel(), ws.interference_free.ravel().astype(float)]
    values = np.column_stack(columns)
    csv_path = _write_csv(names, values, folder / "workspace.csv", int_last=False)
    return [csv_path] + ([plot_workspace(ws, scenario, folder / "workspace.png")] if figures else [])


def write_operability(op, scenario: Scenario, folder: Path, *, figures: bool = True) -> list[Path]:
    """``operability.csv`` (one row per sea state), ``operability.json`` and, with ``figures``,
    ``operability.png`` (:func:`plot_operability`). A wind that follows the sea state (``[wind] with_sea``) adds
    each sea state's wind to the CSV: ``wind_m_s`` (at the wind's reference height) and
    ``wind_direction_deg`` (where it comes from in O)."""
    from marinecdpr.studies.operability import cell_winds

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    names = ["heading_deg", "hs_m", "tp_s", "probability", "operable", "fraction_feasible", "min_margin_N",
             "max_error_m", "realisations", "successes", "success_probability", "success_low", "success_high",
             "controller_bypassed"]
    values = np.array([[r.cell.heading_deg, r.cell.hs, r.cell.tp, r.cell.probability, float(r.operable),
                        r.fraction_feasible, r.min_margin_N, r.max_error_m, r.realisations, r.successes,
                        r.success_probability, *r.interval, r.controller_bypassed] for r in op.results])
    winds = cell_winds(scenario, [r.cell for r in op.results])
    if winds is not None and op.results:
        names += ["wind_m_s", "wind_direction_deg"]
        values = np.column_stack([values, winds])
    paths = [_write_csv(names, values, folder / "operability.csv", int_last=False,
                        int_columns=(names.index("realisations"), names.index("successes"),
                                     names.index("controller_bypassed")))]
    paths.append(write_json(operability_summary(op, scenario), folder / "operability.json"))
    if figures:
        paths.append(plot_operability(op, scenario, folder / "operability.png"))
    return paths


def operability_summary(op, scenario: Scenario) -> dict:
    """``operability.json``'s content: the study's probability of success with its interval,
    per heading, the limiting Hs, and what each means."""
    from marinecdpr.studies.operability import LIMITING_HS_MEANING

    return {
        "scenario": scenario.name,
        "operability": op.operability,
        "operability_interval_95": list(op.interval),
        "operability_meaning": ("probability that the operation succeeds (tensions within the limits less the "
                                "margin for the whole record) in a sea state drawn from the diagram, headings "
                                "equally likely; each sea state's from the share of its realisations that succeed"),
        "realisations": op.results[0].realisations if op.results else 0,
        "margin_N": op.margin_N,
        "min_margin_meaning": ("operability.csv's min_margin_N: the sea state's headroom, the smallest over its "
                               "records' steps of the largest distance to the tension limits any tensions giving "
                               "the wrench could keep, N: the largest margin_N it allows"),
        "per_heading": {f"{h:g}": v for h, v in op.per_heading.items()},
        "per_heading_interval_95": {f"{h:g}": list(v) for h, v in (op.per_heading_interval or {}).items()},
        "limiting_hs_m": op.limiting_hs_json(),
        "limiting_hs_meaning": LIMITING_HS_MEANING,
        "cells": len(op.results),
        "steps_per_cell": op.results[0].n_steps if op.results else 0,
        "realisations_controller_bypassed": sum(r.controller_bypassed for r in op.results),
    }


# ------------------------------------------------------------------------ RAOs, windows
class RaoFiles(NamedTuple):
    """:func:`write_rao`'s result: the RAOs read back from rao.nc, the box approximation
    (both :class:`~marinecdpr.motion.rao.RAO`) and the paths written."""

    bem: Any
    approx: Any
    paths: list


def write_rao(ds, folder: Path, *, made_by: str, box: dict, box_label: str = "box approximation",
              figures: bool = True) -> RaoFiles:
    """A BEM solution's files (:func:`~marinecdpr.motion.bem.hull_bem`): ``rao.nc``
    (Capytaine's dataset, ``source = "capytaine"``), the same table as ``rao.csv``
    (``source = "csv"``, read without the bem extra; its first lines say how it was made)
    and ``rao.png`` beside the box approximation of ``box`` (box_hull_rao's arguments),
    dashed and named ``box_label`` in the legend (with ``figures``; without, no figure).
    Returns :class:`RaoFiles`."""
    import capytaine as cpt

    from marinecdpr.motion.rao import box_hull_rao, read_capytaine, write_rao_csv
    from marinecdpr.report.figures import plot_raos

    folder = Path(folder)
    nc = folder / "rao.nc"
    cpt.export_dataset(str(nc), ds)
    bem = read_capytaine(nc)
    table = folder / "rao.csv"
    where = (f"about {ds.attrs['reference_point']}",) if "reference_point" in ds.attrs else ()
    write_rao_csv(bem, table, comments=(f"RAOs from BEM: {ds.attrs['hull']}", *where, f"made by: {made_by}",
                                        "below the first omega the first row's values hold; above the last, zero"))
    approx = box_hull_rao(**(box | {"roll_damping_ratio": max(box["roll_damping_ratio"], 1e-3)}),
                          omega=bem.omega, heading_deg=bem.heading_deg)
    if not figures:
        return RaoFiles(bem=bem, approx=approx, paths=[nc, table])
    figure = plot_raos(bem, folder / "rao.png", title=f"RAOs from BEM: {ds.attrs['hull']}", beside=approx,
                       beside_label=box_label)
    return RaoFiles(bem=bem, approx=approx, paths=[nc, table, figure])


def _window_rows(w) -> np.ndarray:
    """windows.csv's rows: each window's start, end, length (h) and 1 where the operation fits."""
    d = w.duration_h
    return np.array([[a, b, b - a, float(b - a >= d - 1e-12)] for a, b in w.windows]).reshape(-1, 4)


def windows_summary(series, windows, *, series_name: str, design_limit: str, days) -> dict:
    """``summary.json`` of a weather-window study (:func:`~marinecdpr.studies.weather.weather_windows`):
    the series, the limit, the workable share, the windows, the wait and the probability of
    finishing within each of ``days``; where the series has a wind, the wind limit (null: the
    wind not judged) and, with one, the workable share by Hs alone."""
    w, d = windows, windows.duration_h
    # the wind's keys only where the series has a wind: a series without one writes what it always did
    wind = {} if series.wind_m_s is None else {"wind_limit_m_s": w.wind_limit_m_s}
    alone = {} if w.wind_limit_m_s is None else {"workable_share_hs_alone": w.hs_workable_share}
    return {"series": series_name, "series_hours": float(series.t_h[-1] + series.step_h[-1]),
            "duration_h": d, "alpha": w.alpha, "design_limit": design_limit, **wind,
            "workable_share": w.workable_share, **alone,
            "windows": len(w.windows), "windows_long_enough": w.long_enough,
            "mean_wait_h": None if w.mean_wait_h != w.mean_wait_h else w.mean_wait_h,
            "can_start_share": w.can_start,
            "finish_within_days_probability": {f"{x:g}": w.finish_probability(x) for x in days},
            "meaning": "over start times at each sample, equally likely; the operation needs one window "
                       "of its whole duration" + ("" if series.wind_m_s is None else
                                                   "; a sample is workable when its Hs is within the limit and, "
                                                   "with wind_limit_m_s (null: the wind not judged), its mean wind "
                                                   "at 10 m within that")}


def write_windows(series, windows, folder: Path, *, series_name: str, design_limit: str,
                  days: list[float], figures: bool = True) -> tuple[dict, list[Path]]:
    """A weather-window study's files (:func:`~marinecdpr.studies.weather.weather_windows`):
    ``windows.csv`` (each window, its length, whether the operation fits), ``summary.json``
    and, with ``figures``, ``windows.png``. Returns (the summary, the paths)."""
    from marinecdpr.report.figures import plot_windows

    folder = Path(folder)
    w, d = windows, windows.duration_h
    paths = [_write_csv(["start_h", "end_h", "length_h", "long_enough"], _window_rows(w), folder / "windows.csv")]
    summary = windows_summary(series, w, series_name=series_name, design_limit=design_limit, days=days)
    paths.append(write_json(summary, folder / "summary.json"))
    if not figures:
        return summary, paths
    paths.append(plot_windows(series, w, folder / "windows.png",
                              title=f"Weather windows for a {d:g} h operation (alpha {w.alpha:g})"))
    return summary, paths


def _write_table(names: list[str], rows: list[list], path: Path) -> Path:
    """A CSV of mixed text and number columns (numbers to 10 significant digits)."""
    import csv

    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            out = csv.writer(fh, lineterminator="\n")
            out.writerow(names)
            out.writerows([f"{v:.10g}" if isinstance(v, float) else v for v in row] for row in rows)
    return path


def write_control_study(study, prediction, folder: Path, *, figures: bool = True) -> tuple[dict, list[Path]]:
    """A control study's files (:mod:`marinecdpr.studies.control`): ``control_study.csv`` (a
    row per run), ``prediction.csv`` (the ship-motion predictor's error per horizon and DOF,
    beside the kinematic extrapolation's and the held sample's), ``summary.json`` and, with
    ``figures``, ``control_study.png``. Returns (the summary, the paths)."""
    from dataclasses import asdict

    from marinecdpr.report.figures import plot_control_study
    from marinecdpr.studies.control import moving_dofs, worst_moving_dof

    folder = Path(folder)
    runs = [asdict(r) for r in study.runs]
    header = list(runs[0])
    paths = [_write_table(header, [[r[h] for h in header] for r in runs], folder / "control_study.csv")]
    dofs = ("surge", "sway", "heave", "roll", "pitch", "yaw")
    moving = moving_dofs(prediction)
    rows = [[float(h), dofs[d], *(float(e[i, 0, d]) if np.isfinite(e[i, 0, d]) else "" for e in
                                  (prediction.predictor, prediction.taylor, prediction.hold))]
            for i, h in enumerate(prediction.horizons_s) for d in range(len(dofs)) if moving[d]]
    paths.append(_write_table(["horizon_s", "dof", "predictor", "kinematic", "hold"], rows,
                              folder / "prediction.csv"))
    summary = {"scenario": study.scenario, "mru_rate_hz": study.rate_hz, "duration_s": study.duration_s,
               "judged_from_s": study.settle_s, "runs": runs,
               "controller_bypassed_share_max": study.max_bypassed_share,
               "runs_controller_bypassed": sum(r.controller_verdict == "bypassed" for r in study.runs),
               "prediction_error": {"meaning": "RMS error of the predicted eta over the RMS of eta, worst moving "
                                               "DOF, MRU without latency; null at a horizon where no forecast was "
                                               "compared (the MRU's samples too sparse for the record)",
                                    "horizons_s": prediction.horizons_s.tolist(),
                                    "model_share": prediction.model_share.tolist(),
                                    **{name: [None if np.isnan(v) else float(v)
                                              for v in worst_moving_dof(prediction, err)]
                                       for name, err in (("predictor", prediction.predictor),
                                                         ("kinematic", prediction.taylor),
                                                         ("hold", prediction.hold))}}}
    paths.append(write_json(summary, folder / "summary.json"))
    if figures:
        paths.append(plot_control_study(study, prediction, folder / "control_study.png"))
    return summary, paths
