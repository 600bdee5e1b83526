"""Preloaded in each worker of the local Dask cluster a sea-state study starts
(:class:`marinecdpr.studies.executor.Executor`): the worker ignores Ctrl-C.

Ctrl-C at a terminal goes to the whole process group, the workers too. The study's own
process stops the study and closes the cluster, which ends its workers; a worker that
took the signal itself printed asyncio's ``KeyboardInterrupt`` traceback before the
command's one-line message.
"""

import signal
import threading

if threading.current_thread() is threading.main_thread():
    signal.signal(signal.SIGINT, signal.SIG_IGN)
