"""Each command's contract, for a notebook or a script as for the command line.

A command is a typed specification of its options (:class:`~.base.Spec`: defaults, units,
validation, which options go together; a bad value is one :class:`~.base.SpecError`
naming its field), :func:`estimate` (the run's size, refused where it exceeds the
machine's budget, before any work) and :func:`run` (a frozen result with ``summary()`` and
``write(folder)``). The command line (:mod:`marinecdpr.cli`) maps its options to a spec
and the result to lines, nothing more::

    import marinecdpr
    from marinecdpr.commands import workspace

    sc = marinecdpr.load_scenario("paper")
    spec = workspace.WorkspaceSpec(points=(12, 8))
    print(workspace.estimate(spec, sc).describe())
    result = workspace.run(spec, sc)
    result.map.fraction_feasible        # (12, 8)
    result.write("out")                 # workspace.csv, workspace.png

One module a command; this layer sits between the reports (which draw and write what a
run gives) and the command line.
"""

from marinecdpr.commands.base import Estimate, Spec, SpecError

__all__ = ["Estimate", "Spec", "SpecError"]
