"""Tripwires on where a run's work begins: a machine-independent check that a command was
refused *before* its work started (instead of timing it: no test depends on the machine's
speed).

Every plan, simulation, workspace map and sea-state study goes through one of
:data:`WORK`: the planner's per-chunk step and its whole-series entry, the ship's motion
on a time grid, a sea state's record and its synthesis. A tripwire replaces each with a
function that stops the run at once (in this process: raises :class:`WorkStarted`; in a
child process: exit :data:`TRIPPED` with a line naming it), so a refusal that comes
before them is proven to have cost no work.
"""

from __future__ import annotations

import subprocess
import sys

WORK = (
    ("marinecdpr.motion.basemotion", "evaluate_base_motion"),
    ("marinecdpr.motion.seastate", "sea_record"),
    ("marinecdpr.motion.seastate", "synthesize"),
    ("marinecdpr.planning.planner", "_plan_chunk"),
    ("marinecdpr.planning.planner", "plan_at"),
)
"""(module, function) where work begins. ``evaluate_base_motion`` is patched before the
modules that import it by name (the planner, the simulation) are imported."""
TRIPPED = 99
"""A child's exit code when a tripwire was crossed."""


class WorkStarted(AssertionError):
    """A run's work started (a tripwire was crossed)."""


def arm(monkeypatch) -> None:
    """Tripwires in this process (undone with ``monkeypatch``): each of :data:`WORK`, also
    where it was imported by name. Every module of the package is imported first, so that
    none imported while armed keeps a tripwire after ``monkeypatch`` undoes them."""
    import importlib
    import pkgutil

    import marinecdpr

    for info in pkgutil.walk_packages(marinecdpr.__path__, "marinecdpr."):
        if info.name.endswith("__main__"):
            continue
        try:
            importlib.import_module(info.name)
        except ImportError:  # an optional dependency's module
            pass
    for module, name in WORK:
        mod = importlib.import_module(module)
        real = getattr(mod, name)

        def trip(*args, _name=f"{module}.{name}", **kwargs):
            raise WorkStarted(f"work started: {_name}")

        for other in list(sys.modules.values()):
            if getattr(other, "__name__", "").startswith("marinecdpr") and getattr(other, name, None) is real:
                monkeypatch.setattr(other, name, trip)


PRELUDE = f"""
import importlib, os, runpy, sys

def _tripwire(name):
    def trip(*args, **kwargs):
        sys.stderr.write(f"work started: {{name}}\\n")
        sys.stderr.flush()
        os._exit({TRIPPED})
    return trip

for module, name in {WORK!r}:
    real, trip = getattr(importlib.import_module(module), name), _tripwire(f"{{module}}.{{name}}")
    for other in list(sys.modules.values()):
        if getattr(other, "__name__", "").startswith("marinecdpr") and getattr(other, name, None) is real:
            setattr(other, name, trip)
sys.argv[0] = "marinecdpr"
runpy.run_module("marinecdpr", run_name="__main__", alter_sys=True)
"""
"""A child's program: the tripwires armed, then ``python -m marinecdpr`` with its arguments."""


def run_cli(*args: str, preexec_fn=None, timeout: float = 300.0) -> subprocess.CompletedProcess:
    """``marinecdpr ARGS`` in a child process with the tripwires armed (see :data:`PRELUDE`);
    ``timeout`` only guards against a hang (no assertion on the time taken)."""
    return subprocess.run([sys.executable, "-c", PRELUDE, *args], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=preexec_fn)
