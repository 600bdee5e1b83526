"""The robot: cables, anchors, mass, limits, and the refusal of geometry no pose can use."""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from marinecdpr.scenario.fields import ANCHOR_TOLERANCE_M, CABLES_MAX, FLAT_FRAME_SHARE, CONTROLLED_DOFS, DEGENERATE_RELATIVE, BreakingLoad, Position, RADIUS_OF_GYRATION_RANGE_M, RANK_TOLERANCE, Tension, TensionMax, _KeyedError, _Model, _num, _ranged, UNIT_TOLERANCE, normalised_unit

# --------------------------------------------------------------------------- robot
class Cable(_Model):
    """One cable: where it leaves the frame and where it holds the platform."""

    frame_anchor_m: Position
    """c_i in frame C, m."""
    platform_anchor_m: Position
    """p_i in frame P (origin at the platform's centre of mass), m."""
    tension_min_N: Tension | None = None
    """Smallest allowed tension, N (default: ``robot.tension_min_N``)."""
    tension_max_N: TensionMax | None = None
    """Largest allowed tension, N (default: ``robot.tension_max_N``)."""
    breaking_load_N: BreakingLoad | None = None
    """The load at which this cable breaks, N, not below its ``tension_max_N`` (default:
    ``robot.breaking_load_N``; neither given: unknown, the working limit ``tension_max_N``
    stands in)."""
    pulley_radius_m: _ranged(0.0, 1.0, "m", "a pulley, not a drum the size of a ship") = 0.0
    """A swivelling pulley at the frame anchor (0: the cable leaves a point)."""
    pulley_axis: Any = None
    """The pulley's swivel axis in C, a unit vector along which the cable arrives at the frame
    anchor from its winch (required with a pulley; in the x-z plane for a planar robot)."""

    @field_validator("pulley_axis", mode="after")
    @classmethod
    def _unit_axis(cls, z: Any) -> Any:
        return normalised_unit(z)  # within UNIT_TOLERANCE of unit length: made exactly unit

    @model_validator(mode="after")
    def _check_pulley(self) -> "Cable":
        if self.pulley_radius_m == 0.0:
            if self.pulley_axis is not None:
                raise _KeyedError("pulley_axis", "given without pulley_radius_m")
            return self
        z = self.pulley_axis
        if z is None:
            raise _KeyedError("pulley_axis", "missing: a pulley needs the direction its cable arrives along")
        ok = isinstance(z, (list, tuple)) and len(z) == 3 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in z)
        if not ok:
            raise _KeyedError("pulley_axis", f"must be three finite numbers, got {z!r}")
        if abs(math.sqrt(sum(v * v for v in z)) - 1.0) > UNIT_TOLERANCE:
            raise _KeyedError("pulley_axis", f"must be a unit vector (length 1 within {UNIT_TOLERANCE:g}), "
                                             f"got length {_num(math.sqrt(sum(v * v for v in z)))}")
        return self


class Winch(_Model):
    """The winches behind the cables, all alike (``marinecdpr.model.winch``)."""

    drum_radius_m: _ranged(1e-3, 5.0, "m", "from a bobbin to a mooring drum", above=True)
    gear_ratio: _ranged(1e-3, 1e4, "", "motor turns per drum turn", above=True)
    torque_max_Nm: _ranged(0.0, 1e6, "N m", "a motor's torque", above=True)
    speed_max_rad_s: _ranged(0.0, 1e5, "rad/s", "a motor's speed", above=True)
    power_max_W: _ranged(0.0, 1e8, "W", "a motor's power", above=True)
    rotor_inertia_kg_m2: _ranged(0.0, 1e4, "kg m^2", "a rotor's inertia") = 0.0
    drum_inertia_kg_m2: _ranged(0.0, 1e6, "kg m^2", "a drum's inertia") = 0.0
    gear_efficiency: _ranged(0.0, 1.0, "", "a gearbox's efficiency", above=True) = 1.0
    coulomb_friction_Nm: _ranged(0.0, 1e6, "N m", "a friction torque") = 0.0
    viscous_friction_Nm_s: _ranged(0.0, 1e6, "N m s/rad", "a viscous friction") = 0.0


class Robot(_Model):
    """The cable robot: platform, cables and which degrees of freedom they control."""

    dofs: Literal["planar", "spatial"] = "planar"
    mass_kg: _ranged(1e-3, 1e5, "kg", "a platform from 1 g to 100 t")
    inertia_kg_m2: Any
    """About the centre of mass in P: 3 principal moments or a 3x3 matrix."""
    tension_min_N: Tension | None = None
    tension_max_N: TensionMax | None = None
    breaking_load_N: BreakingLoad | None = None
    """The load at which a cable breaks, N: the default for every cable (each cable's own
    ``breaking_load_N`` overrides it), not below any cable's ``tension_max_N`` that it stands
    for. None (the default): unknown, each cable's working limit ``tension_max_N`` stands in."""
    cables: list[Cable] = Field(min_length=1)
    cable_weight_N_m: _ranged(0.0, 1e4, "N/m", "a rope's weight per metre") = 0.0
    """The cables' weight per metre (their sag: ``marinecdpr.model.catenary``), N/m."""
    clearance_m: _ranged(0.0, 100.0, "m", "a gap to keep, not a distance across the ship") | None = None
    """The least distance a cable may keep to another cable, the platform's body and the
    ``[[obstacles]]`` (``marinecdpr.geometry.interference``), m; 0 flags contact only. The
    plan flags the steps and cables that come closer. None (the default): not checked."""
    winch: Winch | None = None
    """The winches' design: the tension each can give at each step, and its torque, speed,
    power and energy."""

    @field_validator("inertia_kg_m2", mode="before")
    @classmethod
    def _check_inertia(cls, value: Any) -> Any:
        def is_number(x: Any) -> bool:
            return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)

        if isinstance(value, (list, tuple)) and len(value) == 3 and all(map(is_number, value)):
            I = np.diag(np.asarray(value, dtype=float))
            value = tuple(float(v) for v in value)
        elif (isinstance(value, (list, tuple)) and len(value) == 3
              and all(isinstance(r, (list, tuple)) and len(r) == 3 and all(map(is_number, r))
                      for r in value)):
            I = np.asarray(value, dtype=float)
            value = tuple(tuple(float(v) for v in r) for r in value)
        else:
            shown = repr(value)
            raise ValueError(
                "expected 3 principal moments or a 3x3 matrix of numbers, got "
                + (shown if len(shown) <= 60 else shown[:57] + "...")
            )
        scale = max(float(np.abs(I).max()), 1e-300)
        if not np.allclose(I, I.T, rtol=0, atol=1e-12 * scale):
            raise ValueError("inertia matrix is not symmetric")
        eig = np.linalg.eigvalsh(I)
        if eig[0] <= 0:
            raise ValueError(f"inertia is not positive definite (eigenvalues {eig.round(6).tolist()})")
        if eig[0] + eig[1] < eig[2] * (1 - 1e-9):
            raise ValueError(
                "no rigid body has this inertia: principal moments break the triangle "
                f"inequality ({eig[0]:g} + {eig[1]:g} < {eig[2]:g})"
            )
        return value

    @model_validator(mode="after")
    def _check_cables(self) -> "Robot":
        n_dof = len(CONTROLLED_DOFS[self.dofs])
        if len(self.cables) < n_dof:
            raise _KeyedError(
                "cables",
                f"{len(self.cables)} cables cannot control the {n_dof} degrees of freedom "
                f"of a {self.dofs} robot (need at least {n_dof})",
            )
        if len(self.cables) > CABLES_MAX:
            raise _KeyedError("cables", f"must be between {n_dof} and {CABLES_MAX} cables (far more than "
                                        f"any cable robot has), got {len(self.cables)}")
        for i, cable in enumerate(self.cables, start=1):
            lo = cable.tension_min_N if cable.tension_min_N is not None else self.tension_min_N
            hi = cable.tension_max_N if cable.tension_max_N is not None else self.tension_max_N
            for name, val in (("tension_min_N", lo), ("tension_max_N", hi)):
                if val is None:
                    raise _KeyedError(
                        f"cables[{i}].{name}", f"missing, and no robot.{name} default is given"
                    )
            if lo >= hi:
                raise _KeyedError(
                    f"cables[{i}]",
                    f"tension_min_N ({lo:g}) must be below tension_max_N ({hi:g})",
                )
            if cable.breaking_load_N is not None and cable.breaking_load_N < hi:
                raise _KeyedError(f"cables[{i}].breaking_load_N",
                                  f"must not be below the cable's tension_max_N ({hi:g} N), got "
                                  f"{cable.breaking_load_N:g} N (a working limit is at most the breaking load)")
            if cable.breaking_load_N is None and self.breaking_load_N is not None and self.breaking_load_N < hi:
                raise _KeyedError("breaking_load_N",
                                  f"must not be below cable {i}'s tension_max_N ({hi:g} N), got "
                                  f"{self.breaking_load_N:g} N (a working limit is at most the breaking load)")
        # two cables may share a platform point (IPAnema 1's pairs do), not a frame anchor (each
        # leaves its own winch or pulley)
        pts = np.array([c.frame_anchor_m for c in self.cables])
        d = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=-1)
        i, j = np.nonzero(np.triu(d <= ANCHOR_TOLERANCE_M, k=1))
        if i.size:
            raise _KeyedError(f"cables[{j[0] + 1}].frame_anchor_m",
                              f"same frame anchor as cable {i[0] + 1} ({pts[i[0]].tolist()} m)")
        return self

    @model_validator(mode="after")
    def _check_inertia_scale(self) -> "Robot":
        lo, hi = (self.mass_kg * k**2 for k in RADIUS_OF_GYRATION_RANGE_M)
        for moment in np.linalg.eigvalsh(self.inertia):
            if not lo <= moment <= hi:
                k_lo, k_hi = RADIUS_OF_GYRATION_RANGE_M
                raise _KeyedError(
                    "inertia_kg_m2",
                    f"principal moments must be between {_num(lo)} and {_num(hi)} kg m^2 for a "
                    f"{_num(self.mass_kg)} kg platform (radii of gyration from {_num(k_lo)} to "
                    f"{_num(k_hi)} m), got {_num(moment)}",
                )
        return self

    @model_validator(mode="after")
    def _check_planar_pulleys(self) -> "Robot":
        if self.dofs == "planar":
            for i, c in enumerate(self.cables, 1):
                if c.pulley_axis is not None and abs(c.pulley_axis[1]) > 1e-9:
                    raise _KeyedError(f"cables[{i}].pulley_axis",
                                      "must lie in the x-z plane (y = 0) on a planar robot")
        return self

    @model_validator(mode="after")
    def _check_geometry(self) -> "Robot":
        reason = _degenerate_geometry(self)
        if reason:
            raise _KeyedError("cables", reason)
        return self

    # Arrays the numerical layers use.
    @property
    def n_cables(self) -> int:
        return len(self.cables)

    @property
    def controlled(self) -> tuple[int, ...]:
        """Twist components the cables control (indices into (v, omega) in C)."""
        return CONTROLLED_DOFS[self.dofs]

    @property
    def frame_anchors(self) -> np.ndarray:
        """c_i^C, shape (n_cables, 3), m."""
        return np.array([c.frame_anchor_m for c in self.cables], dtype=float)

    @property
    def platform_anchors(self) -> np.ndarray:
        """p_i^P, shape (n_cables, 3), m."""
        return np.array([c.platform_anchor_m for c in self.cables], dtype=float)

    @property
    def pulley_radii(self) -> np.ndarray:
        """Each cable's pulley radius, shape (n_cables,), m (0: none)."""
        return np.array([c.pulley_radius_m for c in self.cables], dtype=float)

    @property
    def pulley_axes(self) -> np.ndarray:
        """Each cable's pulley swivel axis in C, shape (n_cables, 3) (zeros without a pulley)."""
        return np.array([c.pulley_axis if c.pulley_axis is not None else (0.0, 0.0, 0.0) for c in self.cables],
                        dtype=float)

    @property
    def has_pulleys(self) -> bool:
        return bool((self.pulley_radii > 0).any())

    @property
    def inertia(self) -> np.ndarray:
        """I_PP, shape (3, 3), kg m^2, about the centre of mass in P."""
        I = np.asarray(self.inertia_kg_m2, dtype=float)
        return np.diag(I) if I.shape == (3,) else I

    @property
    def tension_min(self) -> np.ndarray:
        """T_min per cable, shape (n_cables,), N."""
        return np.array(
            [c.tension_min_N if c.tension_min_N is not None else self.tension_min_N for c in self.cables],
            dtype=float,
        )

    @property
    def tension_max(self) -> np.ndarray:
        """T_max per cable, shape (n_cables,), N."""
        return np.array(
            [c.tension_max_N if c.tension_max_N is not None else self.tension_max_N for c in self.cables],
            dtype=float,
        )

    @property
    def breaking_load(self) -> np.ndarray:
        """Each cable's breaking load, shape (n_cables,), N: its ``breaking_load_N``, else
        ``robot.breaking_load_N``; where neither is given (unknown) its working limit
        T_max (:attr:`tension_max`) stands in (:attr:`breaking_load_given` says which)."""
        own = [c.breaking_load_N if c.breaking_load_N is not None else self.breaking_load_N for c in self.cables]
        return np.array([t if b is None else b for b, t in zip(own, self.tension_max)], dtype=float)

    @property
    def breaking_load_given(self) -> np.ndarray:
        """Whether each cable's breaking load is given (its own or the robot's
        ``breaking_load_N``), shape (n_cables,) of bool; False: its T_max stands in."""
        return np.array([c.breaking_load_N is not None or self.breaking_load_N is not None for c in self.cables],
                        dtype=bool)


DOF_NAMES = ("x", "y", "z", "theta_x", "theta_y", "theta_z")


def frame_axes(c_C: np.ndarray) -> np.ndarray:
    """The axes of C the frame spans, shape (3,) of bool: those along which the frame
    anchors' range is more than :data:`~marinecdpr.scenario.fields.FLAT_FRAME_SHARE` of the
    frame's largest (and more than 1e-9 of its coordinates' size).

    Parameters
    ----------
    c_C : ndarray, shape (n_cables, 3)
        Frame anchors in C, m.
    """
    extent = np.ptp(c_C, axis=0)
    tol = 1e-9 * max(1.0, float(np.abs(c_C).max()))
    return (extent > tol) & (extent > FLAT_FRAME_SHARE * float(extent.max()))


def _diameter(points: np.ndarray) -> float:
    """Largest distance between two of the points."""
    return float(np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1).max())


def _off_line(points: np.ndarray) -> tuple[float, np.ndarray]:
    """Largest distance of the points from their best-fitting line, and its direction."""
    d = points - points.mean(axis=0)
    axis = np.linalg.svd(d)[2][0]
    return float(np.linalg.norm(d - np.outer(d @ axis, axis), axis=1).max()), axis


def _direction(axis: np.ndarray) -> str:
    """A unit vector as a reader would name it: "along y", or its rounded components."""
    i = int(np.argmax(np.abs(axis)))
    if abs(axis[i]) > 1 - 1e-6:
        return f"along {'xyz'[i]}"
    return "along [" + ", ".join(f"{v:.3g}" for v in axis * np.sign(axis[i])) + "]"


def _degenerate_geometry(robot: Robot) -> str | None:
    """Why no pose gives J~ (eq. 6) full rank on the controlled DOFs, or None.

    Anchors collapsed to a point (within :data:`DEGENERATE_RELATIVE` of the robot's size),
    for a spatial robot anchors on one line, and otherwise J~ rank-deficient (to
    :data:`RANK_TOLERANCE`, moment columns divided by the robot's size) at every one of
    a handful of poses across the frame. A planar robot is judged in the x-z plane.
    """
    from marinecdpr.geometry.kinematics import cable_kinematics
    from marinecdpr.geometry.rotations import matrix_from_euler

    frame, platform = robot.frame_anchors, robot.platform_anchors
    planar = robot.dofs == "planar"
    plane = [0, 2] if planar else [0, 1, 2]
    size_f, size_p = _diameter(frame[:, plane]), _diameter(platform[:, plane])
    size = max(size_f, size_p)
    if size == 0.0:
        return "all anchors coincide: the cables cannot hold the platform"
    tol = DEGENERATE_RELATIVE * size
    where = " in the x-z plane" if planar else ""

    def within(d: float, other: str, other_size: float) -> str:
        if d <= 1e-12 * size:
            return f"coincide{where}"
        return (f"lie within {_num(float(f'{d:.3g}'))} m of each other{where}, less than "
                f"{_num(DEGENERATE_RELATIVE)} of the {other}'s size ({other_size:.3g} m)")

    if size_p <= tol:
        return (f"the platform anchors {within(size_p, 'frame', size_f)}: the cables cannot exert a "
                f"moment on the platform" + (" about y (theta_y)" if planar else ""))
    if size_f <= tol:
        return (f"the frame anchors {within(size_f, 'platform', size_p)}: every cable passes through "
                f"one point, and the cables cannot exert a moment about it")
    if not planar:
        for what, points in (("platform", platform), ("frame", frame)):
            off, axis = _off_line(points)
            if off <= tol:
                near = "" if off <= 1e-12 * size else f", all within {_num(float(f'{off:.3g}'))} m of it"
                return (f"the {what} anchors lie on one line ({_direction(axis)}{near}): every cable meets "
                        f"that line, so the cables cannot turn the platform about it")
    # J~ at the frame's centre and at random poses across (and, for a flat frame, off) it
    controlled = list(robot.controlled)
    lo, hi = frame.min(axis=0), frame.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    half = np.where(half <= tol, size / 2, half)
    rng = np.random.default_rng(0)
    n = 8
    x = centre + rng.uniform(-0.8, 0.8, (n, 3)) * half
    angles = np.radians(rng.uniform(-30.0, 30.0, (n, 3)))
    x[0], angles[0] = centre, 0.0
    if planar:
        x[:, 1] = centre[1]
        angles[:, [0, 2]] = 0.0
    J = cable_kinematics(x, matrix_from_euler(angles), frame, platform).J_tilde[:, :, controlled]
    J[:, :, [k >= 3 for k in controlled]] /= size
    ranks, null = [], None
    for Jk in J:
        if not np.isfinite(Jk).all():
            continue  # a platform anchor on a frame anchor: no direction at this pose
        _, s, vt = np.linalg.svd(Jk)
        rank = int(np.sum(s > RANK_TOLERANCE * s[0]))
        if rank == len(controlled):
            return None
        ranks.append(rank)
        if null is None:
            null = vt[-1]
    if not ranks:
        return None
    dofs = [DOF_NAMES[k] for k, v in zip(controlled, null) if abs(v) > 0.3 * np.abs(null).max()]
    what = dofs[0] if len(dofs) == 1 else "a combination of " + ", ".join(dofs[:-1]) + " and " + dofs[-1]
    return (f"the cables cannot control {what}: the structure matrix J~ has rank {max(ranks)} of "
            f"{len(controlled)} at every pose tried ({len(ranks)} across the frame)")




SCALED_COPY_RELATIVE = 1e-6
"""How close (relative to the platform's size) the platform's anchors must be to a scaled
copy of the frame's for :func:`scaled_copy` to call them one."""


def scaled_copy(robot: Robot) -> float | None:
    """The ratio s if the platform's anchors are a scaled copy of the frame's, else None.

    A scaled copy (p_i = s c_i + b for every cable i, to :data:`SCALED_COPY_RELATIVE` of the
    platform's size; in the x-z plane for a planar robot) makes every level pose singular:
    with the platform level at x, cable i runs along (1 - s) c_i - (x + b), so every cable's
    line passes through the one point (x + b) / (1 - s) (or, for s = 1, all are parallel),
    and no tensions give a moment about it. s < 0 (the same shape turned half a turn, the
    cables crossed) does it too.
    """
    plane = [0, 2] if robot.dofs == "planar" else [0, 1, 2]
    F = robot.frame_anchors[:, plane]
    P = robot.platform_anchors[:, plane]
    F = F - F.mean(axis=0)
    P = P - P.mean(axis=0)
    ff = float(np.sum(F * F))
    size = _diameter(P)
    if ff == 0.0 or size == 0.0:
        return None
    s = float(np.sum(P * F)) / ff
    if float(np.abs(P - s * F).max()) > SCALED_COPY_RELATIVE * size:
        return None
    return s
