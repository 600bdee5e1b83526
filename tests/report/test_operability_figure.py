"""The operability figure's cell numbers (issue 37, item 13): sized to their cells as laid
out (they were 7 pt in cells some 60 pt wide), each inside its cell."""

from types import SimpleNamespace

import numpy as np
import pytest

import marinecdpr.report.figures as figures


def _study(n_hs: int, n_tp: int, headings=(180.0,)):
    rng = np.random.default_rng(3)
    grid = rng.uniform(0.0, 1.0, (n_hs, n_tp))
    grid[0, 0], grid[-1, -1] = 0.999, np.nan  # the widest number ("99.9"), a cell with no sea state
    return SimpleNamespace(
        headings_deg=headings, margin_N=0.0, per_heading={h: 0.5 for h in headings}, per_heading_interval=None,
        results=[SimpleNamespace(realisations=10)],
        scatter=SimpleNamespace(hs=np.arange(1.0, n_hs + 1), tp=np.arange(4.0, 4.0 + 2 * n_tp, 2.0),
                                probability=np.full((n_hs, n_tp), 1.0 / (n_hs * n_tp))),
        probability_grid=lambda h: grid)


@pytest.mark.parametrize("n_hs, n_tp, headings", [(7, 6, (180.0,)), (7, 6, (180.0, 150.0)), (14, 12, (180.0,))])
def test_cell_numbers_fill_their_cells_and_stay_inside(paper, captured_figures, tmp_path, n_hs, n_tp, headings):
    figures.plot_operability(_study(n_hs, n_tp, headings), paper, tmp_path / "operability.png")
    fig = captured_figures["operability.png"]
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes[:len(headings)]:
        box = ax.get_window_extent(renderer)
        cell_w, cell_h = box.width / n_tp, box.height / n_hs
        assert len(ax.texts) == n_hs * n_tp - 1
        sizes = {t.get_fontsize() for t in ax.texts}
        assert len(sizes) == 1  # one size in a panel
        size = sizes.pop()
        assert figures.CELL_FONT_PT[0] <= size <= figures.CELL_FONT_PT[1]
        for t in ax.texts:
            e = t.get_window_extent(renderer)
            j, i = t.get_position()
            x0, y0 = box.x0 + j * cell_w, box.y0 + i * cell_h  # its cell's corner
            assert x0 <= e.x0 and e.x1 <= x0 + cell_w and y0 <= e.y0 and e.y1 <= y0 + cell_h
        widest = max(t.get_window_extent(renderer).width for t in ax.texts)
        tallest = max(t.get_window_extent(renderer).height for t in ax.texts)
        # as large as fits: the widest at 80 % of a cell's width or the tallest at half its height (to the
        # pixel: text extents are whole pixels), or the largest size
        assert widest <= 0.8 * cell_w + 1 and tallest <= 0.5 * cell_h + 1
        assert widest >= 0.8 * cell_w - 2 or tallest >= 0.5 * cell_h - 2 or size == figures.CELL_FONT_PT[1]
    if (n_hs, n_tp) == (7, 6):  # the package's illustrative diagram: numbers well above the old 7 pt
        assert size >= 11.0
