"""The 3D view's axes (issue 37, item 13): a planar robot's flat axis (every point at one y)
is drawn at a readable depth, not squashed to a sliver with its ticks crowded; every axis at
one scale."""

import json
import re

import numpy as np
import pytest

import marinecdpr
LEAST_AXIS_SHARE = 0.35
from marinecdpr.report.view3d import scene_geometry, scene_html


def _scene_layout(html: str) -> dict:
    # the layout plotly writes: Plotly.newPlot(id, data, layout, config)
    call = html[html.index("Plotly.newPlot("):]
    decoder = json.JSONDecoder()
    i = call.index("[")
    _, end = decoder.raw_decode(call, i)
    layout, _ = decoder.raw_decode(call, call.index("{", end))
    return layout["scene"]


@pytest.mark.parametrize("name", ["paper", "paper_clean"])
def test_a_planar_robot_s_flat_axis_keeps_a_readable_depth_at_one_scale(name):
    sc = marinecdpr.load_scenario(name)
    scene = scene_geometry(sc)
    assert np.ptp(scene.frame_anchors[:, 1]) == 0.0  # planar: the frame's anchors all at one y in S
    view = _scene_layout(scene_html(scene, title=name, include_js=False))
    spans = np.array([np.ptp(view[f"{a}axis"]["range"]) for a in "xyz"])
    ratio = np.array([view["aspectratio"][a] for a in "xyz"])
    assert spans[1] >= LEAST_AXIS_SHARE * spans.max() * (1 - 1e-12)  # was 0.2 of it: a sliver
    assert ratio / ratio.max() == pytest.approx(spans / spans.max(), rel=1e-12)  # one scale on every axis
    # the points all inside their ranges
    pts = np.concatenate([scene.frame_anchors, scene.path, scene.cables.reshape(-1, 3)])
    for k, a in enumerate("xyz"):
        lo, hi = view[f"{a}axis"]["range"]
        assert lo <= pts[:, k].min() and pts[:, k].max() <= hi
