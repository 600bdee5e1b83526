"""The elastic cable's law, written once: Hooke's law on the unstretched length.

A straight cable of axial stiffness EA (N) paid out to an unstretched length L0 (m) and
stretched to the length L (m) carries

    T = EA (L - L0) / L0 + c L'      when taut (L > L0; at least 0), 0 when slack,

with c (N s/m) its damping; so its unstretched length at a tension T is L0 = L / (1 + T /
EA) (the winch's length command, the encoders' reading of an elastic cable), its length
at a tension L = L0 (1 + T / EA), and its axial stiffness dT/dL = EA / L0. EA = inf is an
inextensible cable (L0 = L). The heavy cable's elastic catenary
(:mod:`marinecdpr.model.catenary`) integrates the same strain T / EA along its arc.

The functions are plain arithmetic, compiled into their callers in the per-step code and
run on arrays (any broadcastable shapes) from numpy: one expression, the same bits in both.
"""

from __future__ import annotations

from numba import njit
from numba.extending import register_jitable

__all__ = ["elastic_tension", "unstretched_length", "stretched_length", "axial_stiffness"]


@njit(cache=True)
def elastic_tension(L, L0, Ldot, EA, damping):
    """The tension of an elastic cable, N (scalars).

    L (m) its length, L0 (m) its unstretched length, Ldot (m/s) its length's rate, EA (N)
    its axial stiffness, damping (N s/m): EA (L - L0) / L0 + damping Ldot when taut (at
    least 0), 0 when slack.
    """
    if L > L0:
        return max(0.0, EA * (L - L0) / L0 + damping * Ldot)
    return 0.0


@register_jitable
def unstretched_length(L, T, EA):
    """The unstretched length L0 = L / (1 + T / EA) of a cable of length L (m) at the elastic
    tension T (N; the damping's share taken out), stiffness EA (N). Scalars or arrays, m."""
    return L / (1.0 + T / EA)


@register_jitable
def stretched_length(L0, T, EA):
    """The length L0 (1 + T / EA) of a cable of unstretched length L0 (m) at tension T (N),
    stiffness EA (N). Scalars or arrays, m."""
    return L0 * (1.0 + T / EA)


@register_jitable
def axial_stiffness(L0, EA):
    """dT/dL = EA / L0 of a taut cable of unstretched length L0 (m), stiffness EA (N); N/m."""
    return EA / L0
