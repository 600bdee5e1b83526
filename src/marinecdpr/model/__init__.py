"""Model: the robot's dynamics with the ship's motion and the tension methods.

- :mod:`.kernels`   the model as compiled functions of one step (the wrench and its parts,
  eqs. 7-16; forward dynamics; every tension method with the exact QP), and the compiled
  loops that run them over time series;
- :mod:`.dynamics`  the array functions over time series (``wrench_terms``,
  ``forward_dynamics``, ...), each a call of a compiled loop;
- :mod:`.tension`   tension distribution over time series (eqs. 17-20 and Pott's forms);
- :mod:`.brush`     a cleaning brush's loads on the platform (friction, reaction moment, jet).
"""
