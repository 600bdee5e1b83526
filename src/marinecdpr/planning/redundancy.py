"""Does the platform survive a cable's failure? Each cable removed in turn, can the others
still hold the wrench the platform needs within their limits (and the sea's part of it)?

With cable i gone, the wrenches the remaining cables give with tensions within their limits
are a zonotope (:func:`~marinecdpr.model.tension.wrench_faces`): {w : |n_f . (w - c)| <= h_f
for every facet f}. A wrench w is held with every remaining limit tightened by M where
h_f - |n_f . (w - c)| >= M s_f at every facet and M is at most the narrowest remaining range's
half: the largest such M is the margin (:func:`~marinecdpr.model.tension.largest_headroom`'s
headroom, by the facets), N of tension, negative where the wrench is out of reach (by that
much), -inf where the remaining cables lose rank (no tensions hold every direction).

A random part of the wrench (the sea's, the wind's gust: zero-mean Gaussian with covariance
C0 and its rate's C2) reaches k_f sqrt(n_f' C0 n_f) along the facet's normal at its extreme,
k_f given by the caller's ``extreme`` (m0, m2) -> multiples of sigma (e.g. the screen's
Rice extreme over the time the remaining cables must hold the platform): the facet's slack
is h_f - |n_f . (w - c)| - k_f sqrt(n_f' C0 n_f).

A planar robot of k = 3 controlled dofs left with 3 cables has one set of tensions for each
wrench (no redundancy): the zonotope is a parallelepiped, and a wrench inside it is held with
tensions within limits. Whether the wrench lies inside depends on the pose and the load: it
is checked, not assumed (a four-cable robot may survive a failure at some poses and not at
others).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.model.tension import full_rank, wrench_faces

__all__ = ["failure_margins", "single_failure_margin"]


def failure_margins(J: np.ndarray, wrench: np.ndarray, t_min: np.ndarray, t_max: np.ndarray, *,
                    sea: tuple[np.ndarray, np.ndarray] | None = None,
                    extreme: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None) -> np.ndarray:
    """The margin with each cable removed in turn, at each pose (the module's rule).

    Parameters
    ----------
    J : ndarray, shape (n_poses, n_cables, k)
        Controlled columns of J~ at each pose.
    wrench : ndarray, shape (n_poses, k) or (n_poses, n_loads, k)
        The controlled part of the wrench the platform needs, in C (N, N m): one, or several
        at each pose (e.g. the tool still and sliding each way), all of which must be held.
    t_min, t_max : ndarray, shape (n_cables,)
        Tension limits, N.
    sea : (C0, C2), optional
        The covariance of the wrench's random part and of its rate, each
        (n_seas, n_poses, k, k), in the wrench's units.
    extreme : callable(m0, m2) -> ndarray, optional
        The random part's extreme as a multiple of its sigma, from its variance and its
        rate's along a direction (arrays of one shape); needed with ``sea``.

    Returns
    -------
    margin : ndarray, shape (n_poses, n_cables), or (n_seas, n_poses, n_cables) with ``sea``
        Column i: cable i removed. N; -inf where the remaining cables lose rank.
    """
    J = np.asarray(J, dtype=float)
    n, m, k = J.shape
    w = np.asarray(wrench, dtype=float)
    w = w[:, None, :] if w.ndim == 2 else w                                   # (n, L, k)
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (m,))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (m,))
    if sea is not None and extreme is None:
        raise ValueError("failure_margins: a sea's covariance needs its extreme (extreme=)")
    n_seas = 0 if sea is None else np.shape(sea[0])[0]
    out = np.full((n_seas, n, m) if sea is not None else (n, m), -np.inf)
    if m - 1 < k:  # too few cables left to hold every direction
        return out
    for i in range(m):
        keep = np.arange(m) != i
        Jr = J[:, keep]
        ranked = full_rank(Jr)
        faces = wrench_faces(Jr, lo[keep], hi[keep])
        cap = float(np.min(hi[keep] - lo[keep])) / 2.0
        u = np.einsum("nfk,nlk->nlf", faces.normal, w - faces.centre[:, None, :])
        slack = faces.half_width - np.abs(u).max(axis=1)                      # (n, F)
        if sea is None:
            with np.errstate(invalid="ignore", divide="ignore"):
                margin = np.minimum((slack / faces.per_newton).min(axis=1), cap)
            out[:, i] = np.where(ranked, margin, -np.inf)
            continue
        C0, C2 = (np.asarray(a, dtype=float) for a in sea)
        var0 = np.maximum(np.einsum("nfk,snkl,nfl->snf", faces.normal, C0, faces.normal), 0.0)
        var2 = np.maximum(np.einsum("nfk,snkl,nfl->snf", faces.normal, C2, faces.normal), 0.0)
        reach = np.where(var0 > 0.0, np.asarray(extreme(var0, var2), dtype=float) * np.sqrt(var0), 0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            margin = np.minimum(((slack[None] - reach) / faces.per_newton[None]).min(axis=2), cap)
        out[:, :, i] = np.where(ranked[None], margin, -np.inf)
    return out


def single_failure_margin(robot, x_PC_C: np.ndarray, R_PC: np.ndarray, wrench: np.ndarray, *,
                          sea: tuple[np.ndarray, np.ndarray] | None = None,
                          extreme: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None) -> np.ndarray:
    """:func:`failure_margins` of a robot at its poses: per pose, per cable removed, N.

    Parameters
    ----------
    robot : Robot
        Its anchors, limits and controlled dofs (``scenario.robot``).
    x_PC_C : ndarray, shape (n_poses, 3)
        The platform's position in C, m.
    R_PC : ndarray, shape (n_poses, 3, 3)
        Its orientation, R_P^C.
    wrench : ndarray, shape (n_poses, 6) or (n_poses, n_loads, 6)
        The wrench the platform needs (all six components, in C: N, N m); its controlled
        components are held.
    sea : (C0, C2), optional
        Each (n_seas, n_poses, 6, 6): the covariance of the wrench's random part and of its rate.
    extreme : callable(m0, m2) -> ndarray, optional
        As :func:`failure_margins`'.

    Returns
    -------
    margin : ndarray, shape (n_poses, n_cables) or (n_seas, n_poses, n_cables)
        N (>= 0: the remaining cables hold the wrench with cable i gone).
    """
    c = list(robot.controlled)
    x = np.asarray(x_PC_C, dtype=float)
    kin = cable_kinematics(x, np.asarray(R_PC, dtype=float), robot.frame_anchors, robot.platform_anchors,
                           np.zeros((x.shape[0], 6)))
    w = np.asarray(wrench, dtype=float)[..., c]
    if sea is not None:
        sea = tuple(np.asarray(a, dtype=float)[..., c, :][..., :, c] for a in sea)
    return failure_margins(kin.J_tilde[:, :, c], w, robot.tension_min, robot.tension_max, sea=sea, extreme=extreme)
