"""The package's layout: layers import only the layers below them, and no module imports
itself through others (docs/layout.md). Imports inside functions count too."""

import ast
from pathlib import Path

import marinecdpr

PACKAGE = Path(marinecdpr.__file__).parent
LAYERS = (("errors", "textfiles", "memory", "forked", "borrowed", "compiled_cache", "starting", "defaults"), ("geometry",), ("scenario",), ("motion",), ("model",),
          ("planning",), ("control",), ("prototype",), ("studies",), ("report",), ("commands",), ("cli",))


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every marinecdpr module the file imports, at any depth of the code."""
    here = _module_name(path).split(".")
    if path.name != "__init__.py":
        here = here[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(here[:len(here) - node.level + 1] + ([base] if base else []))
            found.add(base)
            found |= {f"{base}.{a.name}" for a in node.names}  # "from pkg import module"
    modules = {_module_name(p) for p in PACKAGE.rglob("*.py")}
    return {m for m in found if m in modules and m != "marinecdpr"}


def _layer(module: str) -> int:
    top = module.split(".")[1]
    for i, names in enumerate(LAYERS):
        if top in names:
            return i
    raise AssertionError(f"{module} is in no layer: add it to LAYERS and docs/layout.md")


GRAPH = {_module_name(p): _imports(p) for p in PACKAGE.rglob("*.py")
         if p.name != "__main__.py" and _module_name(p) != "marinecdpr"}


def test_every_module_is_in_a_layer_and_imports_only_lower_or_equal_layers():
    assert len(GRAPH) > 30
    upward = [f"{m} -> {dep}" for m, deps in GRAPH.items() for dep in deps if _layer(dep) > _layer(m)]
    assert upward == []


def test_no_import_circles():
    # Tarjan's strongly connected components: any component of two or more modules is a circle
    index, low, stack, on, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in GRAPH.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in GRAPH:
        if v not in index:
            visit(v)
    assert circles == []


def test_the_checker_sees_an_upward_import_and_a_circle():
    # the checks above would pass vacuously if the import reader saw nothing
    assert "marinecdpr.geometry.kinematics" in GRAPH["marinecdpr.scenario.robot"]
    assert _layer("marinecdpr.cli.app") > _layer("marinecdpr.report.writers") > _layer("marinecdpr.scenario")
    assert "marinecdpr.control.step" in GRAPH["marinecdpr.prototype.parts.geometry"]
