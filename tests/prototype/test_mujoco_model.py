"""Issue 21, item 13: MuJoCo's warnings never land in the user's folder as MUJOCO_LOG.TXT."""

import mujoco
import numpy as np

from marinecdpr.prototype.mujoco_model import build_model
from marinecdpr.scenario import load_scenario


def test_an_unstable_step_writes_no_mujoco_log_in_the_working_folder(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    built = build_model(load_scenario("paper"))
    data = mujoco.MjData(built.model)
    data.ctrl[:] = np.nan  # MuJoCo's "Nan, Inf or huge value in CTRL ... unstable" warning
    mujoco.mj_step(built.model, data)
    assert data.warning[mujoco.mjtWarning.mjWARN_BADCTRL].number > 0  # the warning did fire
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    assert "unstable" not in capfd.readouterr().out
