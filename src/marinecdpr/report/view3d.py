"""The reports' 3D view: the robot on the ship, drawn in the ship frame S.

:func:`scene_geometry` works out what is drawn, as arrays in S (pure numpy, no plotly);
:func:`scene_html` draws it as an interactive plotly figure (a ``<div>`` for a page);
:func:`view_section` is the report's section around it.

What is drawn, all in S (m; C's origin is ``ship.frame_origin_m``, its axes turned by
``ship.frame_orientation_deg``; a frame carried on a rail, ``[ship.carriage]``, is drawn at
its place at each instant, with the rail):

- the hull: a box of the ship's main dimensions (``base_motion.rao``'s ``length_m``,
  ``beam_m``, ``draught_m`` where a sea state's RAO source gives all three), else an
  illustrative 100 x 20 x 6 m box (:data:`DEFAULT_HULL_M`). The box is where the model
  puts the hull: amidships on the centreline, from the keel up to the waterline, which
  holds S's origin (``docs/conventions.md``, "Where S's origin sits"), so the robot is
  drawn where the ship's rotations move it, not moved to the hull's side. Its freeboard
  is not known and not drawn;
- the frame: its anchors c_i and the box of the anchors' extent, as edges;
- the platform and the cables at a few instants of the plan (the first step, then evenly
  over the run): the convex outline of the platform's anchors
  (:func:`~marinecdpr.geometry.interference.platform_body`) and the straight segments
  from each frame anchor c_i to its platform anchor x_PC + R_PC p_i (over a pulley the
  cable leaves the pulley's rim, near c_i, not c_i itself);
- the planned path of P's origin (the plan's ``pose[:, :3]``), at most
  :data:`PATH_POINTS_MAX` points;
- for a cleaning job, the panel's outline in its plane y = ``trajectory.plane_y_m`` of C.

The ship's motion is not drawn: S moves with the hull.
"""

from __future__ import annotations

import html
from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry.interference import platform_body
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.ship import frame_axes
from marinecdpr.motion.trajectory import evaluate_trajectory
from marinecdpr.planning.planner import Plan
from marinecdpr.scenario.schema import Scenario
from marinecdpr.textfiles import strip_control

__all__ = ["Scene", "scene_geometry", "scene_html", "view_section", "hull_box", "box_edges", "sample_steps",
           "DEFAULT_HULL_M", "PATH_POINTS_MAX", "INSTANTS", "SECTION_TITLE"]

DEFAULT_HULL_M = (100.0, 20.0, 6.0)
"""Length, beam and draught of the illustrative hull drawn when the scenario gives none, m
(those of ``paper_sea``'s box hull)."""
PATH_POINTS_MAX = 2000
"""Most points of the drawn path."""
INSTANTS = 13
"""Instants the platform and cables are drawn at: the first step, then evenly to the last."""
SECTION_TITLE = "The robot on the ship (3D)"

_BOX_CORNERS = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)], dtype=float)
"""The unit cube's corners, (x, y, z) bits of their index."""
_BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5],   # x = 0, x = 1
                       [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],   # y = 0, y = 1
                       [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]],  # z = 0, z = 1
                      dtype=np.int64)
_BOX_EDGES = np.array([[a, b] for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1],
                      dtype=np.int64)


@dataclass(frozen=True)
class Scene:
    """What the 3D view draws, in S (m).

    Attributes
    ----------
    hull_vertices : ndarray, shape (8, 3)
    hull_faces : ndarray of int, shape (12, 3)
        Triangles of ``hull_vertices``.
    hull_label : str
        What the hull box is: of the ship's main dimensions, or illustrative.
    frame_origin : ndarray, shape (3,)
        C's origin in S.
    frame_anchors : ndarray, shape (n_cables, 3)
        c_i in S.
    frame_edges : ndarray, shape (n_frame_edges, 2, 3)
        The edges of the anchors' box (axis-aligned; a flat frame's box is its rectangle).
    times : ndarray, shape (n_instants,)
        The instants drawn, s; the first is the plan's first step.
    platform_edges : ndarray, shape (n_instants, n_edges, 2, 3)
        The convex outline of the platform's anchors at each instant.
    cables : ndarray, shape (n_instants, n_cables, 2, 3)
        Each cable from its frame anchor to its platform anchor at each instant.
    path : ndarray, shape (n_path, 3)
        The planned path of P's origin, at most :data:`PATH_POINTS_MAX` points.
    panel : ndarray, shape (k + 1, 3), optional
        A cleaning job's panel outline, closed (first point repeated); None without.
    frame_moves : ndarray, shape (n_instants, n_frame_edges, 2, 3), optional
        A frame carried on a rail (``[ship.carriage]``): its edges at each instant (then
        ``frame_anchors`` and ``frame_edges`` are its place at the first); None for a frame
        that stands still.
    rail : ndarray, shape (n_rail, 3), optional
        The rail C's origin runs along, sampled; None without a carriage.
    """

    hull_vertices: np.ndarray
    hull_faces: np.ndarray
    hull_label: str
    frame_origin: np.ndarray
    frame_anchors: np.ndarray
    frame_edges: np.ndarray
    times: np.ndarray
    platform_edges: np.ndarray
    cables: np.ndarray
    path: np.ndarray
    panel: np.ndarray | None
    frame_moves: np.ndarray | None = None
    rail: np.ndarray | None = None


def hull_box(base_motion) -> tuple[np.ndarray, np.ndarray, str]:
    """The hull as a box in S: amidships, on the centreline, keel to waterline (z = 0).

    Parameters
    ----------
    base_motion : the scenario's ``[base_motion]``
        A sea state's RAO source gives the box's length, beam and draught where it has all
        three; else the box is :data:`DEFAULT_HULL_M`, labelled illustrative.

    Returns
    -------
    vertices : ndarray, shape (8, 3)
        m, in S.
    faces : ndarray of int, shape (12, 3)
    label : str
    """
    rao = getattr(base_motion, "rao", None)
    dims = None if rao is None else (rao.length_m, rao.beam_m, rao.draught_m)
    if dims is not None and None not in dims:
        label = f"hull: box of its main dimensions ({dims[0]:g} x {dims[1]:g} x {dims[2]:g} m)"
    else:
        dims = DEFAULT_HULL_M
        label = f"hull: illustrative ({dims[0]:g} x {dims[1]:g} x {dims[2]:g} m box)"
    length, beam, draught = (float(v) for v in dims)
    low = np.array([-length / 2, -beam / 2, -draught])
    return low + _BOX_CORNERS * np.array([length, beam, draught]), _BOX_FACES.copy(), label


def box_edges(points: np.ndarray) -> np.ndarray:
    """The edges of the axis-aligned box of ``points`` (n, 3): shape (n_edges, 2, 3), the
    12 of a box, fewer for a flat or linear one (zero-length and repeated edges dropped)."""
    p = np.asarray(points, dtype=float)
    lo, hi = p.min(axis=0), p.max(axis=0)
    corners = lo + _BOX_CORNERS * (hi - lo)
    tol = 1e-12 * max(float(np.max(hi - lo)), 1.0)
    out: list[np.ndarray] = []
    for a, b in _BOX_EDGES:
        edge = corners[[a, b]]
        if np.linalg.norm(edge[1] - edge[0]) <= tol:
            continue
        if any(np.abs(edge - e).max() <= tol or np.abs(edge[::-1] - e).max() <= tol for e in out):
            continue
        out.append(edge)
    return np.array(out, dtype=float).reshape(-1, 2, 3)


def sample_steps(n_steps: int, most: int) -> np.ndarray:
    """At most ``most`` step indices, evenly from 0 to ``n_steps - 1`` (both kept), ascending."""
    if n_steps <= most:
        return np.arange(n_steps)
    return np.unique(np.rint(np.linspace(0.0, n_steps - 1, most)).astype(np.int64))


def _poses(scenario: Scenario, plan: Plan | None, steps: np.ndarray) -> np.ndarray:
    """The plan's poses at ``steps`` (n, 6), in C; without a plan the scenario's trajectory
    at those steps' times, from which a plan takes them."""
    if plan is not None:
        return np.asarray(plan.pose, dtype=float)[steps]
    t = steps * scenario.time.step_s
    return np.asarray(evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship).pose, dtype=float)


def scene_geometry(scenario: Scenario, plan: Plan | None = None, *, instants: int = INSTANTS,
                   path_points: int = PATH_POINTS_MAX) -> Scene:
    """What the 3D view draws (:class:`Scene`), in S.

    Parameters
    ----------
    scenario : Scenario
    plan : Plan, optional
        Its poses; without it, the scenario's trajectory on its time grid (the poses a plan
        has), evaluated only at the steps drawn.
    instants : int
        Most instants the platform and cables are drawn at.
    path_points : int
        Most points of the path.
    """
    n_steps = plan.n_steps if plan is not None else scenario.time.n_steps
    if scenario.ship.carriage is not None:
        return _carried_scene(scenario, plan, n_steps, instants, path_points)
    robot = scenario.robot
    origin = np.asarray(scenario.ship.frame_origin_m, dtype=float)
    R_SC = frame_axes(scenario.ship.frame_orientation_deg) if scenario.ship.turned else None

    def in_S(p_C: np.ndarray) -> np.ndarray:  # points in C (..., 3) to S
        return (p_C if R_SC is None else p_C @ R_SC.T) + origin

    c_S = in_S(robot.frame_anchors)
    at = sample_steps(n_steps, max(int(instants), 1))
    pose = _poses(scenario, plan, at)
    R = matrix_from_euler(pose[:, 3:])                                          # (k, 3, 3), P -> C
    x_C = pose[:, :3]
    p_S = in_S(x_C[:, None, :] + np.einsum("kij,nj->kni", R, robot.platform_anchors))  # (k, n_cables, 3)
    cables = np.stack([np.broadcast_to(c_S, p_S.shape), p_S], axis=2)
    edges_P = platform_body(robot.platform_anchors).edges_P                     # (n_edges, 2, 3)
    platform = in_S(x_C[:, None, None, :] + np.einsum("kij,eaj->keai", R, edges_P))
    path = in_S(_poses(scenario, plan, sample_steps(n_steps, max(int(path_points), 2)))[:, :3])
    panel = None
    if scenario.cleaning is not None:
        xz = np.asarray(scenario.cleaning.panel_m, dtype=float)
        ring = np.vstack([xz, xz[:1]])
        y = float(getattr(scenario.trajectory, "plane_y_m", 0.0))
        panel = in_S(np.column_stack([ring[:, 0], np.full(ring.shape[0], y), ring[:, 1]]))
    vertices, faces, label = hull_box(scenario.base_motion)
    frame_edges = box_edges(c_S) if R_SC is None else in_S(box_edges(robot.frame_anchors))
    return Scene(hull_vertices=vertices, hull_faces=faces, hull_label=label, frame_origin=origin,
                 frame_anchors=c_S, frame_edges=frame_edges, times=at * scenario.time.step_s,
                 platform_edges=platform, cables=cables, path=path, panel=panel)


RAIL_POINTS = 400
"""Points the rail is drawn with."""


def _carried_scene(scenario: Scenario, plan: Plan | None, n_steps: int, instants: int, path_points: int) -> Scene:
    """:func:`scene_geometry` for a frame carried on a rail: C's place and axes on S at each
    instant drawn (``motion.carriage.carriage_motion``), the frame moving with the slider."""
    from marinecdpr.motion.carriage import carriage_motion, rail_of

    robot = scenario.robot
    h = scenario.time.step_s

    def place(steps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # C's origin (k, 3) and axes (k, 3, 3) in S
        r, _, _, R_SC, _, _ = carriage_motion(scenario.ship, steps * h)
        return r, R_SC

    def in_S(p_C: np.ndarray, r: np.ndarray, R_SC: np.ndarray) -> np.ndarray:  # p_C (k, ..., 3), one pose per k
        extra = p_C.ndim - 2
        R = R_SC.reshape(R_SC.shape[:1] + (1,) * extra + (3, 3))
        return np.einsum("...ij,...j->...i", R, p_C) + r.reshape(r.shape[:1] + (1,) * extra + (3,))

    at = sample_steps(n_steps, max(int(instants), 1))
    r, R_SC = place(at)
    k = at.size
    c_S = in_S(np.broadcast_to(robot.frame_anchors, (k,) + robot.frame_anchors.shape), r, R_SC)  # (k, n, 3)
    pose = _poses(scenario, plan, at)
    R = matrix_from_euler(pose[:, 3:])
    x_C = pose[:, :3]
    p_S = in_S(x_C[:, None, :] + np.einsum("kij,nj->kni", R, robot.platform_anchors), r, R_SC)
    cables = np.stack([c_S, p_S], axis=2)
    edges_P = platform_body(robot.platform_anchors).edges_P
    platform = in_S(x_C[:, None, None, :] + np.einsum("kij,eaj->keai", R, edges_P), r, R_SC)
    edges_C = box_edges(robot.frame_anchors)
    frame_moves = in_S(np.broadcast_to(edges_C, (k,) + edges_C.shape), r, R_SC)
    steps = sample_steps(n_steps, max(int(path_points), 2))
    r_p, R_p = place(steps)
    path = in_S(_poses(scenario, plan, steps)[:, :3], r_p, R_p)
    panel = None
    if scenario.cleaning is not None:
        xz = np.asarray(scenario.cleaning.panel_m, dtype=float)
        ring = np.vstack([xz, xz[:1]])
        y = float(getattr(scenario.trajectory, "plane_y_m", 0.0))
        ring_C = np.column_stack([ring[:, 0], np.full(ring.shape[0], y), ring[:, 1]])
        panel = in_S(ring_C[None], r[:1], R_SC[:1])[0]
    rail = rail_of(scenario.ship)
    vertices, faces, label = hull_box(scenario.base_motion)
    return Scene(hull_vertices=vertices, hull_faces=faces, hull_label=label, frame_origin=r[0],
                 frame_anchors=c_S[0], frame_edges=frame_moves[0], times=at * h, platform_edges=platform,
                 cables=cables, path=path, panel=panel, frame_moves=frame_moves,
                 rail=rail.at(np.linspace(0.0, rail.length_m, RAIL_POINTS)).r)


def _segments(edges: np.ndarray) -> tuple[list, list, list]:
    """Segments (n, 2, 3) as plotly's x, y, z lists, each segment ended by None."""
    xs: list = []
    ys: list = []
    zs: list = []
    for a, b in np.asarray(edges, dtype=float).reshape(-1, 2, 3):
        xs += [float(a[0]), float(b[0]), None]
        ys += [float(a[1]), float(b[1]), None]
        zs += [float(a[2]), float(b[2]), None]
    return xs, ys, zs


LEAST_AXIS_SHARE = 0.35
"""Least span of an axis of the view, a share of the largest: a planar robot's flat axis
(its points all at one y) is drawn at a readable depth, its ticks not crowded together."""


def _ranges(points: np.ndarray, pad: float) -> tuple[list[list[float]], dict]:
    """Axis ranges holding ``points`` (n, 3) with ``pad`` of the largest extent each side,
    each at least :data:`LEAST_AXIS_SHARE` of the largest (about the points' middle), and
    the aspect ratio that draws them at one scale (large enough to fill the view)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    size = max(float(np.max(hi - lo)), 0.1)
    lo, hi = lo - pad * size, hi + pad * size
    least = LEAST_AXIS_SHARE * float(np.max(hi - lo))
    middle, half = 0.5 * (lo + hi), 0.5 * np.maximum(hi - lo, least)
    lo, hi = middle - half, middle + half
    span = np.sort(hi - lo)
    ratio = (hi - lo) / np.sqrt(span[2] * span[1])  # the two largest extents' mean scale: fills the view
    return ([[float(a), float(b)] for a, b in zip(lo, hi)],
            {"x": float(ratio[0]), "y": float(ratio[1]), "z": float(ratio[2])})


def _view_args(ranges: list[list[float]], aspect: dict) -> dict:
    return {"scene.xaxis.range": ranges[0], "scene.yaxis.range": ranges[1], "scene.zaxis.range": ranges[2],
            "scene.aspectmode": "manual", "scene.aspectratio": aspect}


CABLE_COLOUR = "#d62728"
PLATFORM_COLOUR = "#1f77b4"


def scene_html(scene: Scene, *, title: str, include_js: bool, div_id: str = "view3d") -> str:
    """The scene as an interactive plotly figure: a ``<div>`` for a page (turn it with the
    mouse, zoom with the wheel), plotly's JS inlined with ``include_js`` (once per page; no
    network). Buttons switch between the robot's extent and the whole ship's; a slider
    moves the platform and cables over :attr:`Scene.times`. The same scene gives the same
    text."""
    import plotly.graph_objects as go

    hv = scene.hull_vertices
    f = scene.hull_faces
    traces = [
        go.Mesh3d(x=hv[:, 0], y=hv[:, 1], z=hv[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2], name=scene.hull_label,
                  color="#7f7f7f", opacity=0.25, flatshading=True, showlegend=True, hoverinfo="name"),
        go.Scatter3d(x=scene.frame_anchors[:, 0], y=scene.frame_anchors[:, 1], z=scene.frame_anchors[:, 2],
                     mode="markers", name="frame anchors", marker={"size": 4, "color": "#2ca02c"}),
    ]
    if scene.frame_moves is None:
        xs, ys, zs = _segments(scene.frame_edges)
        traces.append(go.Scatter3d(x=xs, y=ys, z=zs, mode="lines", name="frame (box of the anchors)",
                                   line={"color": "#2ca02c", "width": 3}, hoverinfo="skip"))
    if scene.rail is not None:
        traces.append(go.Scatter3d(x=scene.rail[:, 0], y=scene.rail[:, 1], z=scene.rail[:, 2], mode="lines",
                                   name="rail (C's origin)", line={"color": "#8c564b", "width": 4}))
    traces.append(go.Scatter3d(x=scene.path[:, 0], y=scene.path[:, 1], z=scene.path[:, 2], mode="lines",
                               name="planned path of P", line={"color": "#ff7f0e", "width": 3}))
    if scene.panel is not None:
        traces.append(go.Scatter3d(x=scene.panel[:, 0], y=scene.panel[:, 1], z=scene.panel[:, 2], mode="lines",
                                   name="panel", line={"color": "#000000", "width": 4}))
    moving = len(traces)  # the platform and the cables: the traces the slider moves

    def instant(k: int) -> list:
        px, py, pz = _segments(scene.platform_edges[k])
        cx, cy, cz = _segments(scene.cables[k])
        out = [go.Scatter3d(x=px, y=py, z=pz, mode="lines", name="platform (outline of its anchors)",
                            line={"color": PLATFORM_COLOUR, "width": 6}, hoverinfo="skip"),
               go.Scatter3d(x=cx, y=cy, z=cz, mode="lines", name="cables",
                            line={"color": CABLE_COLOUR, "width": 3}, hoverinfo="skip")]
        if scene.frame_moves is not None:  # a carried frame moves with the slider
            fx, fy, fz = _segments(scene.frame_moves[k])
            out.append(go.Scatter3d(x=fx, y=fy, z=fz, mode="lines", name="frame (box of the anchors)",
                                    line={"color": "#2ca02c", "width": 3}, hoverinfo="skip"))
        return out

    traces += instant(0)
    robot_points = np.concatenate([scene.frame_anchors, scene.path, scene.cables.reshape(-1, 3),
                                   scene.platform_edges.reshape(-1, 3)]
                                  + ([scene.panel] if scene.panel is not None else [])
                                  + ([scene.frame_moves.reshape(-1, 3)] if scene.frame_moves is not None else []))
    robot_view = _ranges(robot_points, 0.1)
    ship_view = _ranges(np.concatenate([robot_points, scene.hull_vertices]), 0.05)
    names = [f"t = {t:.4g} s" for t in scene.times]
    moved = list(range(moving, moving + (2 if scene.frame_moves is None else 3)))
    frames = [go.Frame(name=names[k], data=instant(k), traces=moved) for k in range(len(names))]
    slider = {"active": 0, "currentvalue": {"prefix": "platform and cables at "}, "pad": {"t": 10},
              "steps": [{"label": f"{t:.3g} s", "method": "animate",
                         "args": [[name], {"mode": "immediate", "frame": {"duration": 0, "redraw": True},
                                           "transition": {"duration": 0}}]}
                        for t, name in zip(scene.times, names)]}
    buttons = [{"label": "the robot", "method": "relayout", "args": [_view_args(*robot_view)]},
               {"label": "the whole ship", "method": "relayout", "args": [_view_args(*ship_view)]}]
    axis = {"backgroundcolor": "#fafafa", "gridcolor": "#dddddd"}
    ranges, aspect = robot_view
    layout = go.Layout(
        title={"text": html.escape(strip_control(title))}, height=700, margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"x": 0.0, "y": 1.0, "bgcolor": "rgba(255,255,255,0.7)"},
        scene={"xaxis": dict(axis, title={"text": "x in S (m)"}, range=ranges[0]),
               "yaxis": dict(axis, title={"text": "y in S (m)"}, range=ranges[1]),
               "zaxis": dict(axis, title={"text": "z in S (m)"}, range=ranges[2]),
               "aspectmode": "manual", "aspectratio": aspect, "domain": {"x": [0.2, 1.0], "y": [0.0, 1.0]},
               "camera": {"eye": {"x": 1.2, "y": -1.6, "z": 0.8}}},
        updatemenus=[{"type": "buttons", "direction": "right", "x": 1.0, "xanchor": "right", "y": 1.0,
                      "yanchor": "top", "buttons": buttons, "showactive": True}],
        sliders=[slider] if len(names) > 1 else [],
    )
    fig = go.Figure(data=traces, layout=layout, frames=frames if len(names) > 1 else None)
    return fig.to_html(full_html=False, include_plotlyjs=bool(include_js), div_id=div_id, auto_play=False,
                       config={"displaylogo": False, "responsive": True})


def view_section(scenario: Scenario, plan: Plan | None = None, *, include_js: bool = True) -> str:
    """The report's section: a heading, one sentence saying what is drawn, the view."""
    scene = scene_geometry(scenario, plan)
    hull = "a box of the ship's main dimensions" if "main dimensions" in scene.hull_label else \
        "an illustrative box hull"
    what = ("In the ship's frame S: " + hull + " up to the waterline, the frame's anchors and their box, the "
            "platform and its cables at the plan's first step (the slider moves them over the run), the planned "
            "path of the platform's centre" + (" and the panel" if scene.panel is not None else "")
            + "; turn the view with the mouse, zoom with the wheel, and show the robot or the whole ship with "
              "the buttons.")
    return (f"<h2>{SECTION_TITLE}</h2>\n<p>{html.escape(what)}</p>\n"
            + scene_html(scene, title=f"{scenario.name} on its ship", include_js=include_js) + "\n")
