"""Model: the robot's dynamics with the ship's motion and the tension methods.

- :mod:`.dynamics`  the wrench the cables must supply (eqs. 7-16), forward dynamics;
- :mod:`.tension`   tension distribution over time series (eqs. 17-20 and Pott's forms);
- :mod:`.kernels`   the same model as compiled functions of one step, and the exact QP.
"""
