"""``[cleaning.surface]`` and ``clean --surface`` refuse what cannot be a job before the work
(issue 37, items 17 and 18): a band too large to tile (counted from its first grid before a
patch is fitted), a tool's stand-off tolerance below a millimetre, a tumblehome side past the
centreline, a move time that makes the hours infinite; they never write a non-finite figure;
a long tiling says how far it is."""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.surface import first_grid, tile_surface
from marinecdpr.report.cleaning import write_surface
from marinecdpr.scenario.loading import load_scenario
from marinecdpr.studies.surface import (
    MAX_SURFACE_PATCHES, MOVE_TIME_MAX_S, SurfaceJob, check_move_time, surface_job, surface_patches,
)
from tests.conftest import one_line_exit_2

runner = CliRunner()
BUILTIN = Path(marinecdpr.__file__).parent / "scenario" / "builtin"


def _scenario(tmp_path: Path, **changes: str) -> Path:
    """paper_clean.toml with keys of its [cleaning.surface] changed, beside its RAO file."""
    text = (BUILTIN / "paper_clean.toml").read_text()
    head, surface = text.split("[cleaning.surface]", 1)
    for key, value in changes.items():
        lines = surface.splitlines()
        i = next(k for k, ln in enumerate(lines) if ln.startswith(f"{key} = "))
        lines[i] = f"{key} = {value}"
        surface = "\n".join(lines) + "\n"
    shutil.copy(BUILTIN / "paper_sea_rao.csv", tmp_path / "paper_sea_rao.csv")
    path = tmp_path / "job.toml"
    path.write_text(head + "[cleaning.surface]" + surface)
    return path


def flat(X, Z):
    return 5.0 + 0.0 * np.asarray(X) * np.asarray(Z)


def test_the_first_grid_is_counted_as_worked_by_hand():
    """A flat side 10 m by 4 m with a 1 x 1 m panel: ceil(10 / 0.98) = 11 stations' pieces and
    ceil(4 / 0.98) = 5 heights', 55 patches, which the tiling keeps whole (flat: no cut)."""
    xs, zs = first_grid(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0)
    np.testing.assert_allclose(xs, np.linspace(0.0, 10.0, 12), atol=1e-12)
    np.testing.assert_allclose(zs, np.linspace(0.0, 4.0, 6), atol=1e-12)
    placements, bad = tile_surface(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0, tolerance_m=0.01)
    assert len(placements) == 55 and not bad
    with pytest.raises(ScenarioError, match=r"the band needs 55 patches of the 1 x 1 m panel, more than the 54 a run"):
        first_grid(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0, max_patches=54)


def test_a_band_too_large_is_refused_before_a_patch_is_fitted(tmp_path, monkeypatch):
    """heights_m = [0, 200] on paper_clean's 200 m Wigley side: its first grid alone counts
    855 040 patches of the 1.3 x 0.8 m panel (the side flares out to 1 296 m from the
    centreline at 200 m: 80 times the half-beam), refused at once; no patch is fitted."""
    import marinecdpr.geometry.surface as gs

    sc = load_scenario(_scenario(tmp_path, heights_m="[0.0, 200.0]"))
    monkeypatch.setattr(gs, "_fit", lambda *a: pytest.fail("a patch was fitted"))
    with pytest.raises(ScenarioError) as err:
        surface_job(sc, move_time_s=600.0)
    assert err.value.key == "cleaning.surface"
    assert f"needs 855,040 patches of the 1.3 x 0.8 m panel, more than the {MAX_SURFACE_PATCHES:,}" in str(err.value)
    with pytest.raises(ScenarioError, match="855,040"):
        surface_patches(sc)
    res = runner.invoke(app, ["clean", str(tmp_path / "job.toml"), "--surface", "--duration", "0.1",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "cleaning.surface: the band needs 855,040 patches")
    assert not (tmp_path / "o").exists()


def test_paper_clean_s_band_is_within_the_budget_as_counted():
    """paper_clean's band: 2 584 patches in its first grid, which the tiling ends with
    2 660 placements (its cuts)."""
    assert surface_patches(load_scenario("paper_clean")) == 2584 < MAX_SURFACE_PATCHES


def test_pieces_cut_beyond_the_budget_are_refused():
    """The ridge of test_issue23_surface: 4 patches in the first grid, cut along the bend to
    the smallest height; a budget of 10 fits stops the cutting with the count."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    with pytest.raises(ScenarioError, match="the band curves so that cutting it into patches flat enough for the "
                                            "tolerance passed the 10 a run may fit"):
        tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=1.0, height_m=1.0, tolerance_m=0.001, max_patches=10)


def test_the_tiling_s_progress_rises_to_the_whole_band():
    """The progress is the settled share of the band's stations x heights: it never falls and
    ends at 1 (the kept and uncleanable patches partition the band)."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    shares: list[float] = []
    placements, bad = tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=0.1, height_m=0.1, tolerance_m=0.001,
                                   progress=shares.append)
    assert bad and len(shares) >= 3
    assert all(b >= a for a, b in zip(shares, shares[1:]))
    assert shares[0] == 0.0 and shares[-1] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("changes, key, words", [
    ({"stand_off_tolerance_m": "1e-9"}, "cleaning.surface.stand_off_tolerance_m", "between 0.001 and 1 m"),
    ({"stand_off_tolerance_m": "0.0"}, "cleaning.surface.stand_off_tolerance_m", "between 0.001 and 1 m"),
    ({"flare": "-1.0", "heights_m": "[0.0, 20.0]"}, "cleaning.surface.heights_m",
     "must stay below 10 m, where the side tumbling home (flare -1) meets the centreline, got 20"),
    ({"flare": "-0.25", "heights_m": "[0.0, 20.0]"}, "cleaning.surface.heights_m", "must stay below 20 m"),
])
def test_impossible_surfaces_are_refused_as_the_scenario_loads(tmp_path, changes, key, words):
    """A tool cannot hold a nanometre of stand-off; a Wigley side with flare f < 0 meets the
    centreline at z = T / sqrt(-f) (1 + f z^2 / T^2 = 0): T = 10 m, f = -1 at 10 m, f = -0.25
    at 20 m (the band's top on it is refused too: no breadth there)."""
    with pytest.raises(ScenarioError) as err:
        load_scenario(_scenario(tmp_path, **changes))
    assert err.value.key == key and words in str(err.value)


def test_a_tumblehome_band_below_the_crossing_is_kept(tmp_path):
    sc = load_scenario(_scenario(tmp_path, flare="-0.25", heights_m="[0.0, 19.9]"))
    assert sc.cleaning.surface.heights_m == (0.0, 19.9)


def test_a_design_study_s_tolerance_below_a_millimetre_is_refused():
    from marinecdpr.scenario.design import Limits

    with pytest.raises(ValueError, match="between 0.001 and 1 m"):
        Limits.model_validate({"stand_off_tolerance_m": 1e-9})


@pytest.mark.parametrize("move", [1e308, MOVE_TIME_MAX_S * 1.0001, -1.0, float("nan"), float("inf")])
def test_a_move_time_beyond_the_cap_is_refused_before_the_tiling(move):
    """With 1e308 s between placements the hours are infinite (written as null before):
    refused by the cap --hull-area's estimate has, before any patch."""
    with pytest.raises(ScenarioError, match="move_time_s: must be a number of seconds from 0 to 1e\\+06"):
        surface_job(load_scenario("paper_clean"), move_time_s=move)
    with pytest.raises(ScenarioError):
        check_move_time(move)
    assert check_move_time(MOVE_TIME_MAX_S) == MOVE_TIME_MAX_S


def test_clean_surface_with_an_endless_move_is_one_line(tmp_path):
    res = runner.invoke(app, ["clean", "paper_clean", "--surface", "--move-time", "1e308",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "--move-time 1e+308", "from 0 to 1e+06")
    assert not (tmp_path / "o").exists()


def test_a_band_with_no_flat_patch_is_refused(tmp_path):
    """A 10 m hull 200 m wide and 0.1 m deep, flared: its side near the bow bends more over
    5 cm than a millimetre's tolerance allows; no placement, no hours (0 h before)."""
    sc = load_scenario(_scenario(tmp_path, length_m="10.0", beam_m="200.0", draught_m="0.1", flare="1.0",
                                 stations_m="[-4.9, -4.7]", heights_m="[0.0, 0.2]",
                                 stand_off_tolerance_m="0.001"))
    with pytest.raises(ScenarioError) as err:
        surface_job(sc, move_time_s=600.0)
    assert err.value.key == "cleaning.surface.stand_off_tolerance_m"
    assert "no patch of the band is flat enough for the tool" in str(err.value)


def test_placements_csv_holds_only_finite_numbers_with_uncleanable_patches(tmp_path):
    """The ridge's uncleanable patches are written with cleanable 0 and no cleaning time (0 s,
    not an empty field): the job's seconds are the cleanable rows' sum."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    placements, bad = tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=1.0, height_m=1.0, tolerance_m=0.001)
    job_s = np.arange(1.0, len(placements) + 1.0)
    sj = SurfaceJob(placements=placements, uncleanable=bad, job_s=job_s, move_time_s=60.0, frame_panel_m=(1.0, 1.0),
                    surface="a ridge")
    path = write_surface(sj, tmp_path)[0]
    rows = list(csv.reader(open(path)))[1:]
    values = np.array(rows, dtype=float)  # an empty field would not parse
    assert len(rows) == len(placements) + len(bad) and np.isfinite(values).all()
    assert (values[:, -1] == 0).sum() == len(bad) and (values[values[:, -1] == 0, 15] == 0.0).all()
    assert values[:, 15].sum() == job_s.sum() == pytest.approx(sj.seconds - (len(placements) - 1) * 60.0)
