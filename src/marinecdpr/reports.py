"""Files a plan produces: ``plan.csv`` and the tension figure (like the paper's figure 5).

Every file is written to a temporary name beside its target and renamed into
place when complete, so an interrupted run never leaves a half-written file.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import numpy as np

from .planning import TWIST_NAMES, Plan
from .scenario import Scenario

__all__ = ["plan_columns", "write_plan_csv", "plot_tensions", "atomic_path"]


@contextmanager
def atomic_path(path: Path, suffix: str = "") -> Iterator[Path]:
    """A temporary path in ``path``'s folder, renamed to ``path`` if the block succeeds."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def plan_columns(plan: Plan, scenario: Scenario) -> tuple[list[str], np.ndarray]:
    """Column names and values of ``plan.csv``.

    Columns: ``t`` (s); the controlled pose in C (``x``, ``z``, ``theta_y`` for a
    planar robot, ``x, y, z, rx, ry, rz`` for a spatial one; m and deg);
    ``L1..Ln`` (cable lengths, m); ``Tpinv1..Tpinvn`` (eq. 18 tensions, N);
    ``T1..Tn`` (the method's tensions, N; empty where infeasible); ``feasible`` (1/0).

    Returns
    -------
    names : list of str
    values : ndarray, shape (n_steps, n_columns)
    """
    dofs = scenario.robot.controlled
    pose_names = ["x", "z", "theta_y"] if scenario.robot.dofs == "planar" else list(TWIST_NAMES)
    pose = plan.pose[:, list(dofs)].copy()
    for col, i in enumerate(dofs):
        if i >= 3:
            pose[:, col] = np.degrees(pose[:, col])
    n = scenario.robot.n_cables
    names = (
        ["t"] + pose_names + [f"L{i}" for i in range(1, n + 1)]
        + [f"Tpinv{i}" for i in range(1, n + 1)] + [f"T{i}" for i in range(1, n + 1)]
        + ["feasible"]
    )
    values = np.column_stack(
        [plan.t, pose, plan.lengths, plan.tensions_pinv, plan.tensions, plan.feasible.astype(float)]
    )
    return names, values


def write_plan_csv(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Write :func:`plan_columns` as CSV (NaN written as an empty field)."""
    names, values = plan_columns(plan, scenario)
    path = Path(path)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(",".join(names) + "\n")
            fmt = ",".join(["%.10g"] * (len(names) - 1) + ["%d"])
            text_rows = (fmt % tuple(row) for row in values)
            fh.write("\n".join(text_rows).replace("nan", ""))
            fh.write("\n")
    return path


def plot_tensions(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Figure like the paper's figure 5: tensions (a) before and (b) after optimisation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    robot = scenario.robot
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True, constrained_layout=True)
    titles = (
        "(a) pseudo-inverse tensions, eq. (18)",
        f"(b) {plan.method.replace('_', ' ')} tensions ({plan.base_model} base)",
    )
    for ax, T, title in zip(axes, (plan.tensions_pinv, plan.tensions), titles):
        for i in range(robot.n_cables):
            ax.plot(plan.t, T[:, i], label=f"cable {i + 1}", lw=1.2)
        for lim, name in ((robot.tension_min, "T_min"), (robot.tension_max, "T_max")):
            for v in np.unique(lim):
                ax.axhline(v, color="k", ls="--", lw=0.8)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_ylabel("tension (N)")
        ax.set_title(title, loc="left", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].legend(ncol=min(4, robot.n_cables), fontsize=8, loc="upper right")
    if not plan.all_feasible:
        bad = ~plan.feasible
        axes[1].fill_between(plan.t, 0, 1, where=bad, color="red", alpha=0.15,
                             transform=axes[1].get_xaxis_transform(), label="infeasible")
    axes[1].set_xlabel("t (s)")
    fig.suptitle(f"Cable tensions: {scenario.name}", fontsize=11)
    path = Path(path)
    with atomic_path(path, suffix=path.suffix) as tmp:
        fig.savefig(tmp, dpi=120)
    plt.close(fig)
    return path
