"""Motion: what moves over time (the ship, the platform's planned path, the loads).

- :mod:`.ship`        the ship's 6-DOF motion record and its rotation kinematics;
- :mod:`.basemotion`  a scenario's ``[base_motion]`` evaluated at times (still, sinusoids,
  sea state, record);
- :mod:`.seastate`    irregular seas: spectra, RAOs, time series;
- :mod:`.rao`         response amplitude operators (a package): the RAO type, CSV tables,
  Capytaine files, the box hull;
- :mod:`.recorded`    measured ship motion from CSV files, smoothed and differentiated;
- :mod:`.trajectory`  the platform's trajectory and the disturbance on it;
- :mod:`.coverage`    boustrophedon coverage paths over a panel, jerk-limited (the cleaning job);
- :mod:`.wind`        the wind's mean profile over height, Frøya's gust spectrum and its series.
"""
