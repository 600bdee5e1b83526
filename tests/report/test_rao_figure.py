"""rao.png: its legend outside the plots (issue 37, item 13: it covered the heave axis's
label and lines)."""

from __future__ import annotations

import numpy as np

from marinecdpr.motion.rao import box_hull_rao
from marinecdpr.report import figures


def test_the_rao_figure_s_legend_covers_no_plot(tmp_path, monkeypatch):
    """Each legend's box on the drawn figure overlaps no axes' box, labels and ticks
    included (matplotlib's tight boxes), and lies inside the figure."""
    kept = []
    real_save = figures._save
    monkeypatch.setattr(figures, "_save", lambda fig, path, **kw: (kept.append(fig), real_save(fig, path, **kw))[1])
    omega = np.linspace(0.2, 1.8, 33)
    kw = dict(length_m=100.0, beam_m=20.0, draught_m=6.0, gm_m=1.5, omega=omega, heading_deg=[90, 120, 150, 180])
    bem, box = box_hull_rao(roll_damping_ratio=0.05, **kw), box_hull_rao(roll_damping_ratio=0.1, **kw)
    path = figures.plot_raos(bem, tmp_path / "rao.png", title="RAOs", beside=box,
                             beside_label="box approximation of the same main dimensions and GM")
    assert path.is_file()
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    (fig,) = kept
    FigureCanvasAgg(fig).draw()  # the figure as saved (its own canvas closed with it)
    renderer = fig.canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert len(legends) == 1 and len(legends[0].get_texts()) == 5  # 4 headings, the dashed lines
    box_ = legends[0].get_window_extent(renderer)
    for ax in fig.axes:
        assert not box_.overlaps(ax.get_tightbbox(renderer)), ax.get_ylabel()
    assert fig.bbox.contains(box_.x0, box_.y0) and fig.bbox.contains(box_.x1, box_.y1)
