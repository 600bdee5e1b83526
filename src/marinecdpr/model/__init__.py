"""Model: the robot's dynamics with the ship's motion and the tension methods.

- :mod:`.rigid_body`  the platform's dynamics as compiled functions of one step (the wrench
  and its parts, eqs. 7-16; forward dynamics) and the compiled loops that run them over
  time series;
- :mod:`.tension_solver`  every tension method, compiled, per step and over time series
  (the exact QP, Pott's improved closed form);
- :mod:`.linalg`    dense linear algebra on small matrices, compiled (LU, Cholesky, the rank
  test), for those two;
- :mod:`.dynamics`  the array functions over time series (``wrench_terms``,
  ``forward_dynamics``, ...), each a call of a compiled loop;
- :mod:`.tension`   tension distribution over time series (eqs. 17-20 and Pott's forms);
- :mod:`.brush`     a cleaning brush's loads on the platform (friction, reaction moment, jet);
- :mod:`.wind`      the wind's drag on the platform and its cables (``[wind]``).
"""
