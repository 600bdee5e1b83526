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

__all__ = ["render_page", "embedded_figures", "literal", "NOT_DRAWN"]

NOT_DRAWN = "Figures not drawn (--no-figures; from Python, figures=False in the spec)."
"""What a page says in place of its figures when they were not drawn."""


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


def embedded_figures(figures: dict[str, Path] | None) -> list[dict] | None:
    """Each figure's caption and its PNG as a ``data:`` address (the page stands alone).

    Parameters
    ----------
    figures : dict of str to Path, or None
        Caption to PNG file, in the page's order; None where the figures were not drawn
        (then None: :func:`render_page` says so in words).
    """
    if figures is None:
        return None
    return [{"caption": caption,
             "src": "data:image/png;base64," + base64.b64encode(Path(p).read_bytes()).decode("ascii")}
            for caption, p in figures.items()]


def render_page(template: str, path: Path, **values) -> Path:
    """The page ``template`` (a file of ``report/templates``) with ``values``, written to
    ``path`` atomically (whole or not at all); returns ``path``. ``figures=None`` (the
    figures not drawn, :func:`embedded_figures`) puts :data:`NOT_DRAWN` where they would be."""
    values["figures_not_drawn"] = NOT_DRAWN if "figures" in values and values["figures"] is None else None
    if values["figures_not_drawn"] is not None:
        values["figures"] = []
    page = _environment().get_template(template).render(**values)
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return path
