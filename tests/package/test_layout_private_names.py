"""No private name crosses a package (issue 38, item 5; docs/layout.md): a name with a
leading underscore is imported, or read as ``module._name``, only inside the folder of
``src/marinecdpr`` that defines it. A package is a folder (``prototype`` and
``prototype/parts`` are two). Imports inside functions count too."""

import ast
from pathlib import Path

import marinecdpr

PACKAGE = Path(marinecdpr.__file__).parent
MODULES = {".".join(p.parts[:-1] if p.parts[-1] == "__init__" else p.parts)  # dotted names of the modules
           for p in (q.relative_to(PACKAGE.parent).with_suffix("") for q in PACKAGE.rglob("*.py"))}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_names_across_packages(path: Path, source: str | None = None) -> list[str]:
    """Every private name that the file at ``path`` takes from another package, as
    ``"file:line name"`` lines: ``from pkg.mod import _name``, a private module on the way
    (``from pkg._mod import name``), and ``alias._name`` where ``alias`` is a module of
    another package bound by an import."""
    rel = path.relative_to(PACKAGE.parent)
    home = ".".join(rel.parts[:-1])  # the importer's folder
    tree = ast.parse(source if source is not None else path.read_text())
    found, aliases = [], {}

    def crossing(module: str) -> bool:
        # the module (or package) lies outside the importer's folder; a package is its own folder
        if not module.startswith("marinecdpr"):
            return False
        folder = module if (PACKAGE.parent / module.replace(".", "/")).is_dir() else module.rpartition(".")[0]
        return folder != home

    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = rel.parts[:-1][:len(rel.parts) - node.level]
                base = ".".join(list(up) + ([base] if base else []))
            if not base.startswith("marinecdpr"):
                continue
            for i, part in enumerate(base.split(".")):
                prefix = ".".join(base.split(".")[:i + 1])
                if _private(part) and crossing(prefix):
                    found.append(f"{rel}:{node.lineno} {base}")
                    break
            for a in node.names:
                full = f"{base}.{a.name}"
                if full in MODULES:  # "from pkg import module"
                    if crossing(full) and _private(a.name):
                        found.append(f"{rel}:{node.lineno} {full}")
                    elif crossing(full):
                        aliases[a.asname or a.name] = full
                elif _private(a.name) and crossing(base):
                    found.append(f"{rel}:{node.lineno} {full}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                if not a.name.startswith("marinecdpr"):
                    continue
                parts = a.name.split(".")
                for i, part in enumerate(parts):
                    if _private(part) and crossing(".".join(parts[:i + 1])):
                        found.append(f"{rel}:{node.lineno} {a.name}")
                        break
                if a.asname and crossing(a.name):
                    aliases[a.asname] = a.name
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and _private(node.attr)
                and isinstance(node.value, ast.Name) and node.value.id in aliases):
            found.append(f"{rel}:{node.lineno} {aliases[node.value.id]}.{node.attr}")
    return sorted(set(found))


def all_private_names_across_packages() -> list[str]:
    return [line for p in sorted(PACKAGE.rglob("*.py")) for line in private_names_across_packages(p)]


def test_no_private_name_is_imported_across_packages():
    assert all_private_names_across_packages() == []


def test_the_checker_sees_each_kind_of_crossing():
    # the test above would pass vacuously if the reader saw nothing
    here = PACKAGE / "prototype" / "parts" / "example.py"
    source = ("from marinecdpr.control.controller import _held, held\n"
              "from ...control import _records\n"
              "from marinecdpr.geometry._vec import norm\n"
              "import marinecdpr.model.rigid_body as rb\n"
              "from marinecdpr.control import step\n"
              "def f():\n"
              "    from ..rig import _local\n"
              "    from .geometry import _same_folder\n"
              "    return rb._x + step._y + step.public\n")
    assert private_names_across_packages(here, source) == [
        "marinecdpr/prototype/parts/example.py:1 marinecdpr.control.controller._held",
        "marinecdpr/prototype/parts/example.py:2 marinecdpr.control._records",
        "marinecdpr/prototype/parts/example.py:3 marinecdpr.geometry._vec",
        "marinecdpr/prototype/parts/example.py:7 marinecdpr.prototype.rig._local",
        "marinecdpr/prototype/parts/example.py:9 marinecdpr.control.step._y",
        "marinecdpr/prototype/parts/example.py:9 marinecdpr.model.rigid_body._x",
    ]
