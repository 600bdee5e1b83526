"""What the commands that run many sea states share (``operability``, ``clean --seas``,
``design``): the executor's options, :class:`ExecutorOptions` (``serial``, ``workers``,
``scheduler``), checked by the executor's own rules and made into one
:class:`~marinecdpr.studies.executor.Executor`."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import model_validator

from marinecdpr.commands.base import Spec, SpecError

if TYPE_CHECKING:
    from marinecdpr.studies.executor import Executor

__all__ = ["ExecutorOptions"]


class ExecutorOptions(Spec):
    """A spec's executor options (a command's spec subclasses this).

    Attributes
    ----------
    serial : bool
        Run in this process, not on Dask (the default for small studies, and without Dask).
    workers : int, optional
        Run on a local Dask cluster of this many worker processes (at most four a core).
    scheduler : str, optional
        Run on a running Dask scheduler at this address (``tcp://host:port``).
    """

    serial: bool = False
    workers: int | None = None
    scheduler: str | None = None

    @model_validator(mode="after")
    def _executor_options(self):
        from marinecdpr.studies.executor import Executor, ExecutorError

        try:  # no network here: the scheduler is asked whether it answers by executor()
            Executor.check(serial=self.serial, workers=self.workers, scheduler=self.scheduler)
        except ExecutorError as exc:
            raise SpecError(exc.option, exc.value, exc.detail) from None
        return self

    def executor(self, steps: int = 0) -> Executor:
        """The executor for ``steps`` of work (:meth:`~marinecdpr.studies.executor.Executor.choose`:
        serial; the scheduler, which must answer; a local cluster of ``workers``; else by
        size).

        Raises
        ------
        SpecError
            Naming ``scheduler`` or ``workers``: no scheduler answers there, Dask is not installed.
        """
        from marinecdpr.studies.executor import Executor, ExecutorError

        try:
            return Executor.choose(serial=self.serial, workers=self.workers, scheduler=self.scheduler, steps=steps)
        except ExecutorError as exc:
            raise SpecError(exc.option, exc.value, exc.detail) from None

    @property
    def processes(self) -> int:
        """The worker processes a run may start on this machine, for its memory check: 1 with
        ``serial``, else ``workers`` or the local cluster's default
        (:data:`~marinecdpr.studies.executor.LOCAL_WORKERS`)."""
        from marinecdpr.studies.executor import LOCAL_WORKERS

        return 1 if self.serial else (self.workers or LOCAL_WORKERS)
