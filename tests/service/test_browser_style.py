"""The pages' look in a real browser (issue 41, "a look that reads as a reference work"): Debian's headless Chromium
driven by Selenium, as tests/service/test_browser.py drives it (its fixtures: the service on loopback, the browser).

What the parsed HTML cannot tell (tests/service/test_page_style.py checks the classes): the numbers' cells are
computed right-aligned in a monospace font and their text ends at one edge in each column; text cells stay left in
the body's font; the chosen model's row and the refused ones are drawn apart; under print media the navigation,
forms and buttons are gone, the text is black on white and an API link is followed by its address; under the dark
scheme the page is dark and axe still finds no violation (its contrast rule: 4.5 for text) on the track, body,
history and refusal pages, every <details> opened so that the comparison table is checked too.
"""
from __future__ import annotations

import pytest

from tests.service.test_browser import _axe_violations, browser, server  # noqa: F401  (fixtures)

EARTH_TRACK = ("/bodies/earth/track?start=2000-01-01&stop=2030-01-01&step_days=3650&tolerance_mas=10"
               "&axis=forced_figure")
REFUSED_TRACK = "/bodies/vesta/track?start=2000-01-01&stop=2200-01-01&step_days=365&tolerance_mas=1"
HISTORY = "/bodies/ceres/history?start_year=-20000&stop_year=0&step_years=500"

#: each table's cells by column: computed alignment, font, and where the text's box ends (a Range over the cell's
#: contents: the text itself, not the cell)
CELLS = """
const out = [];
document.querySelectorAll('table').forEach((table, t) => {
  table.querySelectorAll('tbody tr').forEach(tr => {
    let col = 0;
    for (const cell of tr.children) {
      const style = getComputedStyle(cell), range = document.createRange();
      range.selectNodeContents(cell);
      const text = range.getBoundingClientRect(), box = cell.getBoundingClientRect();
      out.push({table: t, col: col, num: cell.classList.contains('num'), text: cell.textContent.trim(),
                align: style.textAlign, font: style.fontFamily, right: text.right,
                inner: box.right - parseFloat(style.paddingRight) - parseFloat(style.borderRightWidth)});
      col += cell.colSpan;
    }
  });
});
return out;
"""


def _open_details(browser) -> None:
    browser.execute_script("document.querySelectorAll('details').forEach(d => d.setAttribute('open', ''))")


def _media(browser, media: str = "", scheme: str = "light") -> None:
    browser.execute_cdp_cmd("Emulation.setEmulatedMedia", {
        "media": media, "features": [{"name": "prefers-color-scheme", "value": scheme}]})


def _rgb(text: str) -> tuple[float, ...]:
    return tuple(float(x) for x in text[text.index("(") + 1:text.index(")")].split(",")[:3])


def _luminance(rgb: tuple[float, ...]) -> float:
    """WCAG's relative luminance of an sRGB colour (0 black, 1 white)."""
    lin = [(c / 255) / 12.92 if c / 255 <= 0.04045 else ((c / 255 + 0.055) / 1.055) ** 2.4 for c in rgb]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


@pytest.fixture
def media(browser):  # noqa: F811
    yield lambda media="", scheme="light": _media(browser, media, scheme)
    _media(browser)


def test_numbers_are_right_aligned_in_monospace_and_text_is_not(server, browser):  # noqa: F811
    for path in (EARTH_TRACK, "/bodies/moon", "/"):
        browser.get(server + path)
        _open_details(browser)
        cells = browser.execute_script(CELLS)
        numbers = [c for c in cells if c["num"] and c["text"]]
        assert len(numbers) > 30, path
        for c in numbers:
            assert c["align"] == "right" and "monospace" in c["font"], (path, c)
            assert c["font"] != browser.execute_script("return getComputedStyle(document.body).fontFamily")
            assert abs(c["right"] - c["inner"]) <= 1.0, (path, c)       # the text ends at the cell's right edge
        texts = [c for c in cells if not c["num"] and c["text"]]
        assert texts, path
        for c in texts:
            assert c["align"] in ("left", "start") and "monospace" not in c["font"], (path, c)
        # in each column of numbers, every number's last digit stands at one x
        columns: dict[tuple[int, int], set[float]] = {}
        for c in numbers:
            columns.setdefault((c["table"], c["col"]), set()).add(round(c["right"]))
        assert all(max(r) - min(r) <= 1 for r in columns.values()), (path, columns)


def test_the_chosen_model_and_the_refused_ones_are_drawn_apart(server, browser):  # noqa: F811
    browser.get(server + EARTH_TRACK)
    _open_details(browser)
    look = browser.execute_script("""
      const cell = sel => { const c = document.querySelector(sel); const s = getComputedStyle(c);
        return {bg: s.backgroundColor, weight: s.fontWeight, style: s.fontStyle, color: s.color}; };
      return {chosen: cell('tr.chosen > td'), refused: cell('tr.refused > td'),
              plain: cell('table:not(:has(tr.chosen)) tbody td')};""")
    chosen, refused, plain = look["chosen"], look["refused"], look["plain"]
    assert len({chosen["bg"], refused["bg"], plain["bg"]}) == 3, look
    assert int(chosen["weight"]) >= 700 and refused["style"] == "italic" and plain["style"] == "normal", look


def test_a_refusal_is_drawn_apart_from_an_input_error(server, browser):  # noqa: F811
    browser.get(server + REFUSED_TRACK)
    refusal = browser.execute_script("const s = getComputedStyle(document.querySelector('.problem.refusal'));"
                                     "return [s.color, s.borderLeftColor, s.backgroundColor]")
    browser.get(server + "/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=-1")
    error = browser.execute_script("const s = getComputedStyle(document.querySelector('.problem'));"
                                   "return [s.color, s.borderLeftColor, s.backgroundColor]")
    assert all(a != b for a, b in zip(refusal, error)), (refusal, error)


def test_print_shows_the_answer_without_nav_or_forms(server, browser, media):  # noqa: F811
    browser.get(server + EARTH_TRACK)
    media("print")
    hidden = browser.execute_script("""
      return [...document.querySelectorAll('header, nav, form, button, input, select')]
        .filter(e => getComputedStyle(e).display !== 'none' && e.getClientRects().length).map(e => e.outerHTML.slice(0, 80));""")
    assert not hidden, hidden
    shown = browser.execute_script("return [...document.querySelectorAll('main table')].map(t => t.getClientRects().length)")
    assert shown and all(shown), "the tables print"
    body = browser.execute_script("const s = getComputedStyle(document.body); return [s.color, s.backgroundColor]")
    assert _rgb(body[0]) == (0, 0, 0) and _rgb(body[1]) == (255, 255, 255), body
    links = browser.execute_script("""
      return [...document.querySelectorAll('main a[href]')].map(a => [a.getAttribute('href'),
        getComputedStyle(a, '::after').content]);""")
    api = [(href, after) for href, after in links if "/v1/" in href and not href.startswith("data:")]
    assert len(api) >= 3, links
    assert all(href in after for href, after in api), api                 # its address follows the link text
    assert all(after in ("none", "normal", "") for href, after in links if "/v1/" not in href), links
    media()
    assert browser.find_element("css selector", "nav").is_displayed()    # and on screen again


@pytest.mark.parametrize("path", [EARTH_TRACK, "/bodies/vesta", HISTORY, REFUSED_TRACK])
def test_the_dark_scheme_is_dark_and_accessible(server, browser, media, path):  # noqa: F811
    media(scheme="dark")
    browser.get(server + path)
    _open_details(browser)
    body = browser.execute_script("const s = getComputedStyle(document.body); return [s.color, s.backgroundColor]")
    assert _luminance(_rgb(body[1])) < 0.05 < 0.5 < _luminance(_rgb(body[0])), body
    assert not _axe_violations(browser)
    media()
    _open_details(browser)
    assert not _axe_violations(browser)                                 # the light scheme, details open
