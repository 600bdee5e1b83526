"""Progress on stderr: rich's bar on a terminal, plain lines off one, with the time left
once it means something."""

from __future__ import annotations

import time
from contextlib import contextmanager

from rich.markup import escape
from rich.text import Text

from marinecdpr.cli.common import err_console, plain


PROGRESS_LINE_FRACTION = 0.1
"""Off a terminal, a progress line each time another this much of the work is done..."""


PROGRESS_LINE_EVERY_S = 10.0
"""... or when this long has passed since the last line (and a last line at the end)..."""


PROGRESS_LINE_MIN_S = 1.0
"""... but never sooner than this after the last line (a short job prints only its first
line, which says it has started, and its last)."""


ESTIMATE_MIN_PIECES = 3
"""No estimate of the time left before this many pieces of work have been done after the
first (the first holds a first run's compile, and one or two pieces say little)..."""


ESTIMATE_MIN_SHARE = 0.05
"""... nor before they make this share of the work..."""


ESTIMATE_MIN_S = 1.0
"""... nor before they took this long, s (work that comes in batches done at one moment)."""


def seconds(s: float) -> str:
    """``12.3 s`` below a minute, else ``2 min 05 s`` (whole seconds, rounded once)."""
    if s < 59.95:
        return f"{s:.1f} s"
    whole = int(round(s))
    return f"{whole // 60} min {whole % 60:02d} s"


class Pace:
    """A task's pace, measured from the end of its first piece of work (the piece that holds
    a first run's compile, which would swell every estimate), for the time left and the rate."""

    def __init__(self, start: float, eta_after: float = 0.0):
        self.start, self.eta_after = start, eta_after
        self.first: tuple[float, float] | None = None  # (when, done) at the end of the first piece
        self.pieces = 0  # pieces done since the first
        self.last_done = 0.0

    def note(self, done: float, now: float) -> None:
        """Work done so far (``done``, at ``now``)."""
        if self.first is None:
            if done > 0:
                self.first = (now, done)
        elif done > self.last_done:
            self.pieces += 1
        self.last_done = done

    def left_s(self, done: float, total: float | None, now: float) -> float | None:
        """Seconds left at the pace since the first piece; None until it means something:
        :data:`ESTIMATE_MIN_PIECES` pieces since the first, :data:`ESTIMATE_MIN_SHARE` of the
        work and :data:`ESTIMATE_MIN_S` seconds, and more than ``eta_after`` done."""
        if not total or self.first is None or done <= self.eta_after:
            return None
        since, done_then = self.first
        if (self.pieces < ESTIMATE_MIN_PIECES or done - done_then < ESTIMATE_MIN_SHARE * total
                or now - since < ESTIMATE_MIN_S):
            return None
        return (now - since) * (total - done) / (done - done_then)

    def rate(self, done: float, now: float) -> tuple[float, str]:
        """Work per second and what it leaves out: after the first piece where that piece took
        far longer than the pace since (a compile, a start-up), else over the whole time."""
        elapsed = now - self.start
        whole = done / elapsed if elapsed > 0 else float("inf")
        if self.first is None or self.pieces == 0 or now <= self.first[0]:
            return whole, ""
        since, done_then = self.first
        after = (done - done_then) / (now - since)
        first_s = since - self.start
        if first_s > 2.0 * done_then / after + ESTIMATE_MIN_S:
            return after, f" after the first {done_then:g}, which took {seconds(first_s)} with the start-up"
        return whole, ""


def rate_text(per_s: float, per: str) -> str:
    return f"{per_s:.3g} {per}/s" if per_s < 100 else f"{per_s:,.0f} {per}/s"


class PlainProgress:
    """Progress as plain lines on stderr, for pipes and logs; the interface of rich's ``Progress``
    that the commands use (``add_task``, ``update``, a context manager).

    The first task's first line comes at once (the work has started: no silence until the first
    tenth is done); then a line at each tenth of the work or each :data:`PROGRESS_LINE_EVERY_S`,
    with the time left once it can be estimated (:class:`Pace`), and a last line with the rate."""

    def __init__(self, label: str, unit: str = "", eta_after: float = 0.0):
        self.label, self.unit, self.eta_after = label, unit, eta_after
        self._tasks: list[dict] = []

    def __enter__(self) -> "PlainProgress":
        return self

    def __exit__(self, exc_type, *_) -> bool:
        if exc_type is None:  # a last line for work that stopped short of its total
            for task in self._tasks:
                if task["done"] > task["printed"] and not task["finished"]:
                    self._line(task, final=True)
        return False

    def add_task(self, description: str = "", total: float | None = None, unit: str | None = None, **_) -> int:
        now = time.perf_counter()
        first = not self._tasks
        self._tasks.append(dict(description=description, total=total, unit=unit, done=0, printed=0, start=now,
                                printed_at=now, finished=False, started=False, pace=None))
        if first:  # at once: the work has begun, and how much there is
            self._line(self._tasks[-1], started=True)
        return len(self._tasks) - 1

    def update(self, task_id: int, *, completed: float | None = None, total: float | None = None,
               advance: float | None = None, **_) -> None:
        task = self._tasks[task_id]
        now = time.perf_counter()
        if not task["started"]:
            # tasks that run one after another: a task's clock starts when the last one finished
            # (a task that runs alongside the others is updated with 0 done at its start)
            ends = [t["ended"] for t in self._tasks if t["finished"]]
            task.update(start=max([task["start"]] + ends), started=True)
            task["pace"] = Pace(task["start"], self.eta_after)
        if total is not None:
            task["total"] = total
        if completed is not None:
            task["done"] = completed
        if advance is not None:
            task["done"] += advance
        done, total = task["done"], task["total"]
        task["pace"].note(done, now)
        if task["finished"] or done <= task["printed"]:
            return
        tenth = PROGRESS_LINE_FRACTION
        since = now - task["printed_at"]
        if total and done >= total:
            self._line(task, final=True)
        elif since >= PROGRESS_LINE_MIN_S and (
                (total and int(done / total / tenth) > int(task["printed"] / total / tenth))
                or since >= PROGRESS_LINE_EVERY_S):
            self._line(task)

    def _line(self, task: dict, final: bool = False, started: bool = False) -> None:
        now = time.perf_counter()
        elapsed = now - task["start"]
        done, total = task["done"], task["total"]
        name = ": ".join(x for x in (self.label, task["description"]) if x)
        unit = task["unit"] or self.unit
        per = unit or "done"
        unit = f" {unit}" if unit else ""
        of = f"{done:g} of {total:g}{unit}" if total else f"{done:g}{unit}"
        if started:
            text = f"{name}: {of}, started"
        elif final:
            rate = ""
            if elapsed > 0:
                per_s, leaves_out = task["pace"].rate(done, now)
                rate = f" ({rate_text(per_s, per)}{leaves_out})"
            text = f"{name}: {of} in {seconds(elapsed)}{rate}"
        else:
            pct = f" ({100 * done / total:.0f}%)" if total else ""
            left_s = task["pace"].left_s(done, total, now)
            left = "" if left_s is None else f", about {seconds(left_s)} left"
            text = f"{name}: {of}{pct}, {seconds(elapsed)}{left}"
        err_console.print(plain(text), highlight=False, soft_wrap=True)
        if not started:
            task.update(printed=done, printed_at=now, finished=final, ended=now)


def progress_bar(label: str, unit: str = "", eta_after: float = 0.0):
    """Progress on stderr: rich's bar on a terminal, plain lines (:class:`PlainProgress`) otherwise.

    Use as ``with progress_bar("workspace", "poses") as bar: task = bar.add_task("", total=n);
    ... bar.update(task, completed=done, total=n)``; several tasks may share it (named by their
    description). :func:`task_progress` wraps the one-task case. The time left is said once it
    means something (:class:`Pace`), and not before more than ``eta_after`` is done (work in
    runs, each with its own start-up: one run's worth).
    """
    if not err_console.is_terminal:
        return PlainProgress(label, unit, eta_after)
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    paces: dict = {}

    class Bar(Progress):
        """rich's bar, redrawn at each update rather than by a thread of its own: a process with
        no other thread may hand work to a forked copy of itself (:mod:`marinecdpr.forked`)."""

        def update(self, task_id, *args, **kwargs) -> None:
            super().update(task_id, *args, **kwargs)
            task = next(t for t in self.tasks if t.id == task_id)
            pace = paces.setdefault(task_id, Pace(time.perf_counter(), eta_after))
            pace.note(task.completed, time.perf_counter())
            self.refresh()

    class Left(TextColumn):
        """The time left, from the task's pace (rich's own estimate counts a compile in)."""

        def __init__(self):
            super().__init__("")

        def render(self, task) -> Text:
            pace = paces.get(task.id)
            left = None if pace is None or task.finished else pace.left_s(task.completed, task.total,
                                                                          time.perf_counter())
            return Text("" if left is None else f"about {seconds(left)} left", style="progress.remaining")

    return Bar(TextColumn(escape(f"{label:<16}")), TextColumn("{task.description}"), BarColumn(),
               MofNCompleteColumn(), TimeElapsedColumn(), Left(), console=err_console, auto_refresh=False)


@contextmanager
def task_progress(label: str, total: int, unit: str = "", eta_after: float = 0.0):
    """One job's progress on stderr (see :func:`progress_bar`); yields ``update(done, total=None)``."""
    with progress_bar(label, unit, eta_after) as bar:
        task = bar.add_task("", total=total)

        def update(done: int, new_total: int | None = None) -> None:
            bar.update(task, completed=done, total=total if new_total is None else new_total)

        yield update
