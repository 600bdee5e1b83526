"""Several ``marinecdpr`` command lines as processes of their own, forked from one fresh
interpreter that has imported the command line (``marinecdpr.cli.app``) once: each gets its
own exit code and its own stdout and stderr as a real process's, and pays none of the
interpreter's start and imports again (a second or two each on a loaded machine).

Each child runs as ``python -m marinecdpr`` does (``sys.exit(main())``) after its own
set-up code (patches, say), and ends as that process would: its ``SystemExit`` (or any other
exception) leaves the interpreter, with its normal shutdown. The interpreter's flags (``-O``)
are the parent's, for every child.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

CHILDREN = """
import json, os, sys
import marinecdpr.cli.app
cases = json.loads(sys.argv[1])
codes = []
for setup, argv, out, err in cases:
    sys.stdout.flush(); sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        for fd, path in ((1, out), (2, err)):
            os.dup2(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644), fd)
        exec(setup, {"__name__": "__setup__"})
        sys.argv = ["marinecdpr", *argv]
        sys.exit(marinecdpr.cli.app.main())
    codes.append(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]))
print(json.dumps(codes))
"""


def run_forked(cases: list[tuple[str, list[str]]], *, flags: tuple[str, ...] = (), timeout: float = 300.0
               ) -> list[tuple[int, str, str]]:
    """Run each ``(setup code, argv)`` of ``cases`` as a child of one ``python *flags``
    interpreter; return each child's (exit code, stdout, stderr), in order."""
    with tempfile.TemporaryDirectory() as d:
        rows = [(setup, list(argv), str(Path(d) / f"{i}.out"), str(Path(d) / f"{i}.err"))
                for i, (setup, argv) in enumerate(cases)]
        res = subprocess.run([sys.executable, *flags, "-c", CHILDREN, json.dumps(rows)], capture_output=True,
                             text=True, timeout=timeout)
        assert res.returncode == 0, res.stderr
        codes = json.loads(res.stdout)
        return [(code, Path(out).read_text(), Path(err).read_text()) for code, (_, _, out, err) in zip(codes, rows)]
