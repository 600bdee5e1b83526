"""Studies: many plans or runs, and what they say.

- :mod:`.prototype_runs`  the three runs of the main job and their error bounds;
- :mod:`.workspace`       where on the frame the platform can be held at sea;
- :mod:`.operability`     in which sea states the robot can work;
- :mod:`.coverage`        the area a brush cleaned along a path, on a raster (passes per cell);
- :mod:`.cleaning`        the cleaning job: coverage path flown closed loop, measured.
"""
