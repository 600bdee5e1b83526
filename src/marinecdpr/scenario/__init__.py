"""Scenario: what the user describes (the first layer; imports only the geometry below it).

- :mod:`.fields`    field types with ranges and units, shared constants;
- :mod:`.robot`     cables, anchors, mass and limits; refusal of degenerate geometry;
- :mod:`.cleaning`  the cleaning job's panel, brush and contact; the coverage trajectory;
- :mod:`.wind`      the wind: its speed, profile, gust and the drag's coefficients;
- :mod:`.schema`    ship, base motion, trajectory, disturbance, time, planning, simulation;
  the :class:`Scenario` itself;
- :mod:`.scale`     warnings for robots far outside cable-robot scale;
- :mod:`.messages`  a validation error as one line naming the key;
- :mod:`.loading`   TOML files and the built-in scenarios (``builtin/*.toml``).
"""

from marinecdpr.scenario.fields import CONTROLLED_DOFS, SHIP_DOFS, TENSION_METHODS
from marinecdpr.scenario.loading import builtin_scenarios, load_scenario, scenario_from_dict
from marinecdpr.scenario.robot import Cable, Robot
from marinecdpr.scenario.scale import scale_warnings
from marinecdpr.scenario.schema import Scenario

__all__ = ["Scenario", "Robot", "Cable", "load_scenario", "builtin_scenarios", "scenario_from_dict",
           "SHIP_DOFS", "CONTROLLED_DOFS", "TENSION_METHODS", "scale_warnings"]
