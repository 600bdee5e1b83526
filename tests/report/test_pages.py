"""The reports' HTML pages (issue 38, item 4): one template and one stylesheet, every value
escaped and read literally."""

from html.parser import HTMLParser
from importlib import resources
from types import SimpleNamespace

import pytest

from marinecdpr.report.page import render_page

HOSTILE = "<script>alert('x')</script> & \x1b[31mred\x1b[0m \"quoted\""
SHOWN = "<script>alert('x')</script> & [31mred[0m \"quoted\""  # the control characters gone, the rest as typed


class _Page(HTMLParser):
    """The page's elements and text, as a browser reads them."""

    def __init__(self):
        super().__init__()
        self.tags, self.text, self.style, self._in = [], [], [], None

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self._in = tag

    def handle_endtag(self, tag):
        self._in = None

    def handle_data(self, data):
        (self.style if self._in == "style" else self.text).append(data)


def _values(template: str) -> dict:
    common = dict(figures=[], view="")
    if template == "simulate.html":
        return dict(common, name=HOSTILE, description=HOSTILE, facts=[("robot", HOSTILE)], title="Tracking errors",
                    header=["max |error|", HOSTILE], table=[("x (mm)", [(HOSTILE, True)])], notes=[HOSTILE],
                    budget=[(HOSTILE, "1 mm", "2 N", "–", HOSTILE)], held=None)
    if template == "clean.html":
        return dict(common, name=HOSTILE, description=HOSTILE, facts=[("robot", HOSTILE)], numbers=[(HOSTILE, "1")],
                    notes=[HOSTILE], variants=[HOSTILE], comparison=[("area", [HOSTILE])])
    spec = SimpleNamespace(name=HOSTILE, description=HOSTILE, seed=3, targets=SimpleNamespace(hours=24.0, sea_share=0.8))
    return dict(common, spec=spec, candidates="4 candidates", feasible=2, verdict=HOSTILE, limits=HOSTILE,
                objective="power (kW)", rows=[[HOSTILE, "3 x 2"]], flown=HOSTILE)


@pytest.mark.parametrize("template", ["simulate.html", "clean.html", "design.html"])
def test_every_page_escapes_what_it_shows_and_shares_the_one_stylesheet(template, tmp_path):
    page = render_page(template, tmp_path / "report.html", **_values(template)).read_text(encoding="utf-8")
    parsed = _Page()
    parsed.feed(page)
    assert "script" not in parsed.tags and "\x1b" not in page
    text = "".join(parsed.text)
    assert text.count(SHOWN) >= 3  # the title's, the heading's and the tables': each as typed
    assert parsed.tags.count("style") == 1
    css = (resources.files("marinecdpr.report") / "templates" / "style.css").read_text(encoding="utf-8")
    assert "".join(parsed.style).strip() == css.strip()
