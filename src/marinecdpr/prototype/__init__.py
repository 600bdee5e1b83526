"""The virtual prototype: a plan flown on a physics plant, open or closed loop.

- :mod:`.simulation`    the 1 ms exchange loop and :func:`simulate`;
- :mod:`.mujoco_model`  the MuJoCo model of robot and ship built from a scenario.
"""
