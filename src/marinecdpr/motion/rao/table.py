"""The RAO table: :class:`RAO` (six DOFs over wave frequency and heading), the DOF order
and the limits every RAO source is held to. The conventions are the package's
(:mod:`marinecdpr.motion.rao`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NoReturn

import numpy as np

__all__ = ["DOFS", "RAO", "ROTATIONS", "OMEGA_MAX_RAD_S", "TRANSLATION_RAO_MAX_M_M", "ROTATION_RAO_MAX_DEG_M",
           "out_of_range", "Fail"]

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""The DOF order of :attr:`RAO.values` (first axis)."""

ROTATIONS = np.array([False, False, False, True, True, True])
"""Which of :data:`DOFS` are rotations (rad/m; deg/m in a CSV table)."""

# Limits of what the RAO readers accept: far beyond any ship, they refuse garbage
# (1e300, a unit off by 1000) without second-guessing a real table.
OMEGA_MAX_RAD_S = 100.0
"""Largest wave frequency in an RAO table, rad/s: a 6 mm wave (period 0.063 s)."""
TRANSLATION_RAO_MAX_M_M = 100.0
"""Largest surge, sway or heave RAO, m/m (real ones are about 1; a table in mm/m is refused)."""
ROTATION_RAO_MAX_DEG_M = 1000.0
"""Largest roll, pitch or yaw RAO, deg/m (17.5 rad/m). A lightly damped small hull's linear
roll peak is a few hundred deg/m; a potential-flow table without viscous roll damping can
exceed this at resonance, and then needs that damping."""

Fail = Callable[[str], NoReturn]
"""A reader's ``fail(message)``: raises its one-line error naming the file."""


@dataclass(frozen=True)
class RAO:
    """A ship's RAOs tabulated over wave frequency and heading.

    Attributes
    ----------
    omega : ndarray, shape (n_omega,)
        Wave angular frequencies, rad/s, strictly increasing, > 0.
    heading_deg : ndarray, shape (n_heading,)
        Wave headings beta (direction the waves travel towards, from S's +x,
        counter-clockwise), deg, strictly increasing, in [0, 360).
    values : ndarray of complex, shape (6, n_heading, n_omega)
        RAO of ``(surge, sway, heave, roll, pitch, yaw)`` in S: m/m for
        translations, rad/m for rotations; the argument is the phase lead over
        the wave elevation at S's origin (:mod:`marinecdpr.motion.rao`).

    The arrays are stored as read-only copies (float64 and complex128).
    """

    omega: np.ndarray
    heading_deg: np.ndarray
    values: np.ndarray

    def __post_init__(self) -> None:
        omega = np.array(self.omega, dtype=float)
        heading = np.array(self.heading_deg, dtype=float)
        values = np.array(self.values, dtype=complex)
        if omega.ndim != 1 or omega.size == 0:
            raise ValueError(f"omega must have shape (n_omega,) with n_omega >= 1; got {omega.shape}")
        if heading.ndim != 1 or heading.size == 0:
            raise ValueError(f"heading_deg must have shape (n_heading,) with n_heading >= 1; "
                             f"got {heading.shape}")
        if values.shape != (6, heading.size, omega.size):
            raise ValueError(f"values must have shape (6, n_heading, n_omega) = "
                             f"(6, {heading.size}, {omega.size}); got {values.shape}")
        if not (np.all(np.isfinite(omega)) and np.all(omega > 0.0)):
            raise ValueError("omega must be finite and > 0 rad/s")
        if np.any(np.diff(omega) <= 0.0):
            raise ValueError("omega must be strictly increasing")
        if not (np.all(np.isfinite(heading)) and np.all(heading >= 0.0) and np.all(heading < 360.0)):
            raise ValueError("heading_deg must be in [0, 360)")
        if np.any(np.diff(heading) <= 0.0):
            raise ValueError("heading_deg must be strictly increasing")
        if not np.all(np.isfinite(values)):
            raise ValueError("values must be finite")
        for a in (omega, heading, values):
            a.flags.writeable = False
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "heading_deg", heading)
        object.__setattr__(self, "values", values)

    def at(self, omega: np.ndarray, heading_deg: float | np.ndarray) -> np.ndarray:
        """The RAOs at given wave frequencies and heading, interpolated.

        Linear interpolation of the complex values: in omega between tabulated
        frequencies (the value at the smallest tabulated omega below it, zero
        above the largest), and in heading with wrap-around over 360 deg (one
        tabulated heading is used for all headings).

        Parameters
        ----------
        omega : array_like, shape (n,) or scalar
            Wave angular frequencies, rad/s.
        heading_deg : float or array_like broadcastable to omega's shape
            Wave heading(s) beta, deg (any real value; taken modulo 360).

        Returns
        -------
        ndarray of complex, shape (6, n)
            RAO of ``(surge, sway, heave, roll, pitch, yaw)``: m/m and rad/m.
        """
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        if w.ndim != 1:
            raise ValueError(f"omega must be a scalar or have shape (n,); got {w.shape}")
        h = np.broadcast_to(np.asarray(heading_deg, dtype=float), w.shape)
        # omega: bracketing indices i0, i1 and weight t (clipped: constant below, zero above)
        tab = self.omega
        if tab.size == 1:
            i0 = np.zeros(w.size, dtype=np.intp)
            i1 = i0
            t = np.zeros(w.size)
        else:
            i0 = np.clip(np.searchsorted(tab, w, side="right") - 1, 0, tab.size - 2)
            i1 = i0 + 1
            t = np.clip((w - tab[i0]) / (tab[i1] - tab[i0]), 0.0, 1.0)
        above = w > tab[-1]
        # heading: bracketing indices j0, j1 over the circle and weight s
        hd = self.heading_deg
        n_h = hd.size
        if n_h == 1:
            j0 = np.zeros(w.size, dtype=np.intp)
            j1 = j0
            s = np.zeros(w.size)
        else:
            hm = np.mod(h, 360.0)
            ext = np.concatenate(([hd[-1] - 360.0], hd, [hd[0] + 360.0]))
            k = np.clip(np.searchsorted(ext, hm, side="right") - 1, 0, n_h)
            s = (hm - ext[k]) / (ext[k + 1] - ext[k])
            j0 = np.mod(k - 1, n_h)  # ext[k] is heading k - 1 (mod n_h)
            j1 = np.mod(k, n_h)
        v = self.values
        lo = v[:, j0, i0] * (1.0 - t) + v[:, j0, i1] * t
        hi = v[:, j1, i0] * (1.0 - t) + v[:, j1, i1] * t
        out = lo * (1.0 - s) + hi * s
        out[:, above] = 0.0
        return out


def out_of_range(omega: np.ndarray, heading: np.ndarray, values: np.ndarray) -> str | None:
    """What is beyond the limits in an RAO table (rad/m for rotations), or None."""
    if (i := np.flatnonzero(omega > OMEGA_MAX_RAD_S)).size:
        return f"omega {omega[i[0]]:g} rad/s is above {OMEGA_MAX_RAD_S:g} rad/s; expected wave frequencies in rad/s"
    amp = np.abs(values)
    limit = np.where(ROTATIONS, math.radians(ROTATION_RAO_MAX_DEG_M), TRANSLATION_RAO_MAX_M_M)
    over = amp > limit[:, None, None]
    if over.any():
        d, h, w = np.argwhere(over)[0]
        unit = "rad/m" if ROTATIONS[d] else "m/m"
        return (f"{DOFS[d]} RAO {amp[d, h, w]:g} {unit} at omega {omega[w]:g} rad/s, heading "
                f"{heading[h]:g} deg is above {limit[d]:.3g} {unit}; expected a ship's response")
    return None

