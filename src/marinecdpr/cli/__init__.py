"""The command line: options to a command's spec, its result to printed lines.

:mod:`.app` is the ``marinecdpr`` command (its group, Ctrl-C, the entry point); one module
per command (:mod:`.plan`, :mod:`.simulate`, :mod:`.clean`, ...) maps its options to the
library's contract (:mod:`marinecdpr.commands`) and prints what it finds; :mod:`.common`
holds the consoles, the one-line failures and the output folder, :mod:`.progress` the
progress lines and bar, :mod:`.seas` what the sea-state studies share."""
