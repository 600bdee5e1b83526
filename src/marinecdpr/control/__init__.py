"""Control: the controller a robot runs, and the virtual prototype with it.

- :mod:`.records`     the controller's records: model, plan, gains, measurement, command;
- :mod:`.step`        the compiled step, from one exchange's measurements to the commands;
- :mod:`.controller`  :class:`Controller`, built from a scenario, to call from a user's loop.
"""

from marinecdpr.control.controller import Controller

__all__ = ["Controller"]
