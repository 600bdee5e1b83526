"""The reports' HTML pages: one base template and one stylesheet, each page a template of
its own that fills the base's body (Jinja2, which escapes every value it is given).

A page's values are text and numbers, never HTML: the template escapes them (``<``, ``&``,
quotes) and :func:`literal` strips their control characters (a terminal's escapes in a
user's names), as the command line prints them. Only HTML built by the toolkit itself (the
3D view's section) passes as :class:`markupsafe.Markup`."""

from __future__ import annotations

import base64
from functools import lru_cache
from pathlib import Path

from marinecdpr.report.files import atomic_path
from marinecdpr.textfiles import strip_control

__all__ = ["render_page", "embedded_figures", "literal"]


def literal(value: object) -> object:
    """A value as the page shows it: text without control characters (escaped by the
    template afterwards); HTML the toolkit built (``Markup``) and other values as they are."""
    from markupsafe import Markup

    if isinstance(value, str) and not isinstance(value, Markup):
        return strip_control(value)
    return value


@lru_cache(maxsize=1)
def _environment():
    from jinja2 import Environment, PackageLoader, StrictUndefined

    return Environment(loader=PackageLoader("marinecdpr.report", "templates"), autoescape=True, finalize=literal,
                       undefined=StrictUndefined, trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True)


def embedded_figures(figures: dict[str, Path]) -> list[dict]:
    """Each figure's caption and its PNG as a ``data:`` address (the page stands alone).

    Parameters
    ----------
    figures : dict of str to Path
        Caption to PNG file, in the page's order.
    """
    return [{"caption": caption,
             "src": "data:image/png;base64," + base64.b64encode(Path(p).read_bytes()).decode("ascii")}
            for caption, p in figures.items()]


def render_page(template: str, path: Path, **values) -> Path:
    """The page ``template`` (a file of ``report/templates``) with ``values``, written to
    ``path`` atomically (whole or not at all); returns ``path``."""
    page = _environment().get_template(template).render(**values)
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return path
