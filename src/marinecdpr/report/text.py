"""The words of a report, for the terminal and the HTML page, and the page itself: the
tracking-error table, what the numbers say, the base motion in a line."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from marinecdpr.planning.planner import TWIST_NAMES
from marinecdpr.report.figures import RUN_TITLES, _pose_names, length_unit
from marinecdpr.report.view3d import view_section
from marinecdpr.scenario.schema import Scenario

if TYPE_CHECKING:
    from marinecdpr.studies.prototype_runs import PrototypeFigures, RunFigures

__all__ = ["write_report_html", "error_table", "findings", "describe_base_motion", "beyond_text"]


def _sim_runs(f: PrototypeFigures) -> dict[str, RunFigures]:
    """The figures' runs, in the report's order."""
    return {r: f.runs[r] for r in ("open_loop", "closed_loop", "fixed_base_open_loop") if r in f.runs}


def _error_rows(f: PrototypeFigures, scenario: Scenario) -> list[tuple[str, str, list[float], float | None]]:
    """(label, kind, each run's value, the paper's value or None) of every tracking error:
    each controlled DOF, the spatial rotation angle, and the largest cable-length error.
    kind is "m" or "deg"."""
    runs = list(_sim_runs(f).values())
    paper = f.paper_reported
    rows = []
    for name, i in zip(*_pose_names(scenario)):
        if i < 3:
            key = f"max_abs_error_{TWIST_NAMES[i]}_m"
            rows.append((name, "m", [r.max_abs_error(TWIST_NAMES[i]) for r in runs],
                         paper.get(key) if paper else None))
        elif scenario.robot.dofs == "planar":
            key = "max_abs_error_theta_deg"
            rows.append((name, "deg", [r.max_abs_error_theta_deg for r in runs], paper.get(key) if paper else None))
        else:
            rows.append((name, "deg", [r.max_abs_error(name) for r in runs], None))
    if scenario.robot.dofs != "planar":
        rows.append(("rotation angle", "deg", [r.max_abs_error_theta_deg for r in runs], None))
    rows.append(("cable length", "m", [max(r.max_abs_cable_length_error_m) for r in runs],
                 paper.get("max_abs_cable_length_error_m") if paper else None))
    return rows


def error_table(f: PrototypeFigures, scenario: Scenario) -> tuple[list[str], list[list[str]]]:
    """The tracking errors as text: header and rows, one unit per row (chosen from its
    largest value), the paper's column only for the paper's experiment, a row saying which
    runs stayed within the error bound, and (where a run has a controller) a last row saying
    whether its controller held or was bypassed (``controller_verdict``)."""
    paper = f.paper_reported is not None
    header = ["max |error|"] + (["paper (Adams, open loop)"] if paper else []) + [RUN_TITLES[r] for r in _sim_runs(f)]
    rows = []
    for label, kind, values, paper_value in _error_rows(f, scenario):
        everything = values + ([paper_value] if paper_value is not None else [])
        size, unit = (1.0, "deg") if kind == "deg" else length_unit(max(everything))
        cells = [f"{v / size:.3g}" for v in values]
        lead = ([f"{paper_value / size:.3g}" if paper_value is not None else "–"] if paper else [])
        rows.append([f"{label} ({unit})"] + lead + cells)
    size, unit = length_unit(f.error_bound_m)
    rows.append([f"within {f.error_bound_m / size:.3g} {unit} / {f.error_bound_deg:g} deg"]
                + (["–"] if paper else [])
                + ["yes" if r.within_error_bound else "NO: " + beyond_text(r.beyond_error_bound)
                   for r in _sim_runs(f).values()])
    if any(r.controller_verdict is not None for r in _sim_runs(f).values()):
        rows.append(["controller"] + (["–"] if paper else [])
                    + [_controller_cell(r, f.steps) for r in _sim_runs(f).values()])
    return header, rows


def _controller_cell(run: RunFigures, steps: int | None) -> str:
    if run.controller_verdict is None:
        return "–"
    of = f" of {steps}" if steps else ""
    return (("held" if run.controller_verdict == "held" else "BYPASSED")
            + f" ({run.controller_fallbacks}{of} steps fed the plan)")


def beyond_text(names: Sequence[str]) -> str:
    """``["x", "rz", "cable 1", "cable 2", "cable 3", "cable 5"]`` as "x, rz, cables 1-3, 5"."""
    cables = [int(n.split()[1]) for n in names if n.startswith("cable ")]
    parts = [n for n in names if not n.startswith("cable ")]
    runs: list[str] = []
    for i in cables:
        if runs and runs[-1][1] == i - 1:
            runs[-1] = (runs[-1][0], i)
        else:
            runs.append((i, i))
    if runs:
        text = ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs)
        parts.append(("cable " if len(cables) == 1 else "cables ") + text)
    return ", ".join(parts)


def _times(ratio: float) -> str:
    """A ratio for a sentence: 3.56, 61 100 (not 6.11e+04)."""
    return f"{ratio:.3g}" if ratio < 1000 else f"{float(f'{ratio:.3g}'):,.0f}".replace(",", " ")


def _fmt_length(v: float) -> str:
    size, unit = length_unit(v)
    return f"{v / size:.3g} {unit}"


def findings(f: PrototypeFigures, scenario: Scenario, *, warnings: bool = True) -> list[str]:
    """What the numbers say, as sentences written from them (for the report and terminal);
    with ``warnings``, the figures' warnings too."""
    runs = _sim_runs(f)
    out = []
    bound = f"{_fmt_length(f.error_bound_m)} and {f.error_bound_deg:g} deg"

    def worst(r: str) -> tuple[float, float]:
        run = runs[r]
        return max(run.largest_position_error_m, max(run.max_abs_cable_length_error_m)), run.max_abs_error_theta_deg

    for r, run in runs.items():
        pos, ang = worst(r)
        verdict = ("within the bound" if run.within_error_bound else
                   "BEYOND the bound (" + beyond_text(run.beyond_error_bound) + ")")
        out.append(f"{RUN_TITLES[r]}: largest position or cable-length error {_fmt_length(pos)}, "
                   f"angle {ang:.3g} deg: {verdict} of {bound}.")
    ideal = scenario.simulation.cables.model == "ideal"
    if "open_loop" in runs:
        pos, _ = worst("open_loop")
        if not runs["open_loop"].within_error_bound:
            out.append("Open loop leaves its plan: tensions fed forward without feedback do not hold this "
                       "robot on its path" + (" (with ideal cables plan and plant share one model, so this is "
                                              "the platform's open-loop instability, not a modelling error)"
                                              if ideal else "") + "; judge the robot by the closed loop.")
        elif ideal and pos < 1e-3 * f.error_bound_m:
            out.append("With ideal cables the plan and the plant share one model: open loop follows the plan "
                       "but for the hold of the tensions over each step.")
    st = f.stability
    if st is not None:
        mode = ", ".join(st["mode"])
        if st["verdict"] == "unstable":
            out.append(f"The open loop is unstable: linearised along the plan ({st['winches']}-controlled winches) "
                       f"it has a mode in {mode} that grows at {st['open_loop_growth_rate_1_s']:.3g} 1/s (an error "
                       f"e-folds every {st['e_folding_time_s'] * 1e3:.3g} ms; worst at t = {st['t_s']:.3g} s): "
                       "only feedback holds this robot.")
        else:
            out.append(f"The open loop is {st['verdict']} ({st['winches']}-controlled winches): linearised along the "
                       f"plan, its largest growth rate is {st['open_loop_growth_rate_1_s']:.2g} 1/s (mode in {mode}).")
    if "closed_loop" in runs:
        closed = runs["closed_loop"]
        if closed.controller_verdict == "bypassed":
            from marinecdpr.studies.prototype_runs import bypassed_text

            out.append("The closed loop FAILED: " + bypassed_text(closed.controller_fallbacks, f.steps,
                                                                 f.controller_bypassed_share_max) + ".")
        elif not closed.within_error_bound:
            out.append("The closed loop too leaves the bound: the feedback gains, the sensors or the "
                       "cables do not hold this robot on its plan.")
        else:
            out.append("The closed loop holds the platform within the bound.")
    if "open_loop" in runs and "fixed_base_open_loop" in runs:
        # against the error bound: the moving-base plan's open-loop error with ideal cables is
        # only the hold of the tensions over each step, no yardstick
        fixed, moving = worst("fixed_base_open_loop")[0], worst("open_loop")[0]
        limit = f.error_bound_m
        if fixed > 2 * moving:
            against = (f"{_times(fixed / limit)} times the error bound of {_fmt_length(limit)}" if fixed > limit else
                       f"{100 * fixed / limit:.3g} % of the error bound of {_fmt_length(limit)}")
            out.append(f"The fixed-base plan, which leaves out the ship's motion, errs by {_fmt_length(fixed)}, "
                       f"{against}: what ignoring the ship costs.")
    if f.paper_reported is not None:
        out.append("The paper's column is its section 4.2: open loop on Adams with a 1 ms exchange.")
    out += [f"Warning: {w}." for w in f.warnings] if warnings else []
    for r, run in runs.items():
        if run.tension_limit_excess_N > 0:
            out.append(f"{RUN_TITLES[r]}: applied tensions left their limits by up to "
                       f"{run.tension_limit_excess_N:.3g} N.")
    return out


def _budget_cell(value: float | None, scale: float, unit: str) -> str:
    return "–" if value is None else f"{value * scale:.3g} {unit}"


def write_report_html(f: PrototypeFigures, scenario: Scenario, figures: dict[str, Path] | None, path: Path, *,
                      plan=None) -> Path:
    """One self-contained page: the scenario, the error table (beside the paper's for the
    paper's experiment), what the numbers say, every figure (``figures``: caption to PNG;
    None: the page says they were not drawn), and the robot on the ship in 3D
    (:func:`~marinecdpr.report.view3d.view_section`, at ``plan``'s poses, else the scenario's
    trajectory's)."""
    from markupsafe import Markup

    from marinecdpr.report.page import embedded_figures, render_page

    header, rows = error_table(f, scenario)
    table = [(row[0], [(c, c.startswith("NO")) for c in row[1:]]) for row in rows]
    lead = [("–", False)] if f.paper_reported is not None else []
    table.append(("applied tensions", lead + [
        (f"{r.tension_min_N:.1f} .. {r.tension_max_N:.1f} N", False) for r in _sim_runs(f).values()]))
    limits = f"{scenario.robot.tension_min.min():g} .. {scenario.robot.tension_max.max():g} N"
    table.append((f"tension limits ({limits})", lead + [
        ("within", False) if r.tension_limit_excess_N == 0 else
        (f"outside by {r.tension_limit_excess_N:.3g} N", True) for r in _sim_runs(f).values()]))
    sim = scenario.simulation
    r = scenario.robot
    facts = [
        ("robot", f"{r.dofs}, {r.n_cables} cables, {r.mass_kg:g} kg, tensions "
                  f"{r.tension_min.min():g} .. {r.tension_max.max():g} N"),
        ("base motion", describe_base_motion(scenario.base_motion)),
        ("trajectory", scenario.trajectory.type),
        ("time", f"{scenario.time.duration_s:g} s at {scenario.time.step_s * 1e3:g} ms "
                 f"({f.steps} steps)"),
        ("tensions", f"{f.method.replace('_', ' ')}: {f.opt_tension_min_N:.1f} .. "
                     f"{f.opt_tension_max_N:.1f} N (pseudo-inverse, eq. 18, alone: down to "
                     f"{f.pinv_tension_min_N:.1f} N)"),
        ("plant", f"{sim.plant} ({sim.integrator}), cables {sim.cables.model}"
                  + (f", EA {sim.cables.stiffness_EA_N:g} N, {sim.cables.winch} winch, lag "
                     f"{sim.cables.winch_time_constant_s * 1e3:g} ms" if sim.cables.model != "ideal" else "")),
        ("closed loop", f"computed torque, bandwidth {sim.control.bandwidth_hz:g} Hz, damping ratio "
                        f"{sim.control.damping_ratio:g}"),
    ]
    budget = [(name, _budget_cell(e["length_change_m"], 1e3, "mm"), _budget_cell(e["tension_change_N"], 1.0, "N"),
               _budget_cell(e.get("workspace_change"), 100.0, "%"), e["note"])
              for name, e in f.error_budget.items()]
    held = f.error_budget_workspace_held_share_point
    built = any(e.get(k) is not None for e in f.error_budget.values()
                for k in ("length_change_m", "tension_change_N", "workspace_change"))
    return render_page(
        "simulate.html", path, name=scenario.name, description=scenario.description, facts=facts,
        title="Tracking errors, the paper's and ours" if f.paper_reported is not None else "Tracking errors",
        header=header, table=table, notes=findings(f, scenario),
        budget=budget if built else None,  # only where the scenario builds something beyond point anchors
        held=None if held is None else f"{held * 100:.1f} %",
        figures=embedded_figures(figures), view=Markup(view_section(scenario, plan)))


def describe_base_motion(bm) -> str:
    """One line describing a ``[base_motion]`` of any type."""
    if bm.type == "still":
        return "still"
    if bm.type == "sinusoidal":
        return "sinusoidal: " + ", ".join(
            f"{c.dof} {c.amplitude_deg if c.amplitude_deg is not None else c.amplitude_m:g}"
            f"{' deg' if c.amplitude_deg is not None else ' m'} / {c.period_s:g} s" for c in bm.components)
    if bm.type == "sea_state":
        spectrum = {"jonswap": "JONSWAP", "pierson_moskowitz": "Pierson-Moskowitz"}[bm.spectrum]
        return (f"sea state: {spectrum}, Hs {bm.hs_m:g} m, Tp {bm.tp_s:g} s, heading {bm.heading_deg:g} deg, "
                f"spreading {bm.spreading}, RAOs from {bm.rao.source.replace('_', ' ')}, seed {bm.seed}")
    if bm.type == "recorded":
        return (f"recorded: {Path(bm.file).name} (z {bm.z_axis}, angles in {bm.angles}, "
                f"from {bm.start_s:g} s of the record)")
    return bm.type
