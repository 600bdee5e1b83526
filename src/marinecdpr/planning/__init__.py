"""Planning: a scenario's trajectory turned into cable tensions, step by step.

- :mod:`.planner`  :func:`plan`, :func:`iter_plan` (bounded memory), :class:`Plan`;
- :mod:`.verdicts` why a plan cannot be flown, in words: the infeasible steps, the cables at
  their limits, the limit to change or method to try, singular poses, cables too close;
- :mod:`.budget`   how much memory and time a run needs, and refusal of runs that do not fit;
- :mod:`.interference` how close the cables come to each other, the platform and the obstacles.
"""
