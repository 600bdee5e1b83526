"""Ctrl-C while the ``marinecdpr`` command starts: one line and exit 130, from the first line
the package runs (before its cache is configured and the command's module is imported),
so that no interrupt meets Python's default handler, whose traceback a user would see.
:mod:`marinecdpr.cli.app` replaces the handler once it can handle an interrupt itself."""

from __future__ import annotations

import os
import signal
import sys

__all__ = ["interrupted_while_starting", "run_as_the_command", "catch_while_starting"]


def interrupted_while_starting(signum, frame) -> None:  # pragma: no cover - timing
    """Ctrl-C while the command loads (its imports, before :func:`~marinecdpr.cli.app.main`):
    one line, exit 130. Nothing has been written yet, and nothing needs tidying."""
    os.write(2, b"error: interrupted\n")
    os._exit(130)


def run_as_the_command() -> bool:
    """Is this process the ``marinecdpr`` command (its console script, ``python -m
    marinecdpr`` or ``python -m marinecdpr.cli``), not a program that imports the package
    (a test, or a worker multiprocessing spawned, which runs its parent's script under
    another name)?"""
    main_module = sys.modules.get("__main__")
    spec = getattr(main_module, "__spec__", None)
    if spec is not None:
        return spec.name in ("marinecdpr.__main__", "marinecdpr.cli.__main__")
    return os.path.basename(getattr(main_module, "__file__", None) or "") == "marinecdpr"


def catch_while_starting() -> None:
    """Set :func:`interrupted_while_starting` for SIGINT if this process is the command and
    the handler is still Python's default. Idempotent."""
    if run_as_the_command() and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, interrupted_while_starting)
