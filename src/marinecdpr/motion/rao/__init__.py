"""Response amplitude operators (RAOs) of the ship's six DOFs in regular waves.

Conventions (fixed throughout the package):

* **DOF order** ``(surge, sway, heave, roll, pitch, yaw)`` in the ship frame S
  (x forward, y to port, z up; roll, pitch and yaw right-handed about +x, +y, +z).
  Translations in m per m of wave amplitude, rotations in **rad** per m of wave
  amplitude (files may use deg/m; see :func:`read_rao_csv`).
* **Time convention**: a regular wave of amplitude ``a`` and phase ``eps`` has the
  elevation ``zeta(t) = Re(a exp(i (omega t + eps)))`` at S's origin, and the ship
  responds with ``eta_j(t) = Re(RAO_j a exp(i (omega t + eps)))``. So ``|RAO_j|`` is
  the amplitude ratio and ``arg(RAO_j)`` the phase **lead** of the motion over the
  wave elevation at S's origin.
* **Wave heading** ``beta`` (deg): the direction the waves travel towards, from the
  ship's +x axis, counter-clockwise about +z. 0 = following seas, 90 = waves
  travelling towards +y (coming from starboard), 180 = head seas. In [0, 360).

So a long wave (omega -> 0) makes the ship follow the sea surface: heave -> 1,
pitch -> i k cos(beta) and roll -> -i k sin(beta) (k = omega^2 / g), because
the surface ``zeta = a exp(i (omega t - k (x cos beta + y sin beta)))`` rises
towards the bow (pitch down is positive) and towards port (roll up to port is
positive) a quarter period after it rises at the origin.

The package, one module per idea:

- :mod:`.table`     the RAO type (:class:`RAO`), the DOF order and the limits every
  source is held to;
- :mod:`.csvfile`   a CSV table (:func:`read_rao_csv`, :func:`write_rao_csv`);
- :mod:`.capytaine` a NetCDF file from the BEM code Capytaine (:func:`read_capytaine`);
- :mod:`.boxhull`   a built-in box-hull approximation (:func:`box_hull_rao`).
"""

from marinecdpr.motion.rao.boxhull import ROLL_GYRADIUS_OVER_BEAM, box_hull_rao, check_positive
from marinecdpr.motion.rao.capytaine import MAX_NETCDF_BYTES, NETCDF3_MAGIC, read_capytaine
from marinecdpr.motion.rao.csvfile import PHASE_MAX_DEG, read_rao_csv, write_rao_csv
from marinecdpr.motion.rao.table import (
    DOFS, OMEGA_MAX_RAD_S, RAO, ROTATION_RAO_MAX_DEG_M, TRANSLATION_RAO_MAX_M_M,
)

__all__ = [
    "DOFS",
    "RAO",
    "read_rao_csv",
    "write_rao_csv",
    "read_capytaine",
    "box_hull_rao",
    "ROLL_GYRADIUS_OVER_BEAM",
    "check_positive",
    "OMEGA_MAX_RAD_S",
    "TRANSLATION_RAO_MAX_M_M",
    "ROTATION_RAO_MAX_DEG_M",
    "PHASE_MAX_DEG",
    "MAX_NETCDF_BYTES",
    "NETCDF3_MAGIC",
]
