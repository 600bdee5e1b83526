"""Geometry: rotations, small-vector algebra on arrays and the cables' kinematics (eqs. 1-6).

The foundation every layer may use: pure functions of poses and anchors, no scenario.

- :mod:`.rotations`   Euler angles, rotation matrices, angular velocity and acceleration;
- :mod:`.vec`         3-vectors as component lists over ``(n_steps,)`` arrays;
- :mod:`.kinematics`  cable vectors, lengths and the structure matrix J~ (eqs. 1-6);
- :mod:`.elastic`     the elastic cable's law (Hooke's law on the unstretched length);
- :mod:`.polygons`    plane polygons: area, points inside, distance to the boundary;
- :mod:`.interference` distances between segments, to planes, boxes and the platform's hull.
"""
