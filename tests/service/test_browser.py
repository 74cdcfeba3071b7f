"""The web page in a real browser: Debian's headless Chromium, driven by Selenium through chromedriver's path, against
the service run by uvicorn on loopback.

Each form is submitted as a person would (typing, clicking) and its result checked against the API's numbers; the
permalink reloads to the same page; the CSV download is the whole track; an error stands at its field; no request
leaves loopback (Chromium's own network log); axe-core (vendored: tests/service/vendor/axe-core) finds no
accessibility violation on any page type; a screenshot of each page type is saved (``EPHEM_TEST_ARTIFACTS``, default
a temporary directory).

The browser is Debian's (``apt-get install chromium chromium-driver``; ``.ci/run`` installs it when missing): under
CI (``CI`` set) a missing browser fails these tests, elsewhere they skip saying how to install it.
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[2]
AXE = Path(__file__).resolve().parent / "vendor" / "axe-core" / "axe.min.js"
#: axe-core 4.14.1's axe.min.js (tests/service/vendor/axe-core/README.md)
AXE_SHA256 = "29348999450cdf2849a8e70b7912fc2da85a849da39c0d0d5394f51d4a9ed95c"
INSTALL = "apt-get install chromium chromium-driver (Debian's packages; a browser downloaded elsewhere is refused here)"


def _executables() -> tuple[str, str] | None:
    chromium = os.environ.get("EPHEM_CHROMIUM") or shutil.which("chromium")
    driver = os.environ.get("EPHEM_CHROMEDRIVER") or shutil.which("chromedriver")
    return (chromium, driver) if chromium and driver else None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def server():
    port = _free_port()
    env = {**os.environ, "EPHEM_WARM_UP": "0"}
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "service.app:app", "--host", "127.0.0.1",
                             "--port", str(port), "--log-level", "warning"], cwd=ROOT, env=env)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                with urllib.request.urlopen(base + "/healthz", timeout=1):
                    break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise
                time.sleep(0.2)
        yield base
    finally:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.fixture(scope="module")
def browser():
    found = _executables()
    if found is None:
        if os.environ.get("CI"):
            pytest.fail(f"no Chromium or chromedriver for the browser tests under CI: {INSTALL}")
        pytest.skip(f"no Chromium or chromedriver: {INSTALL}")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    chromium, driver_path = found
    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-default-apps", "--disable-extensions", "--window-size=1280,1000",
                # every name but loopback resolves to nothing: the page cannot reach out even if it tried
                "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1"):
        opts.add_argument(arg)
    opts.set_capability("goog:loggingPrefs", {"performance": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=driver_path), options=opts)
    driver.set_page_load_timeout(60)
    try:
        yield driver
    finally:
        driver.quit()


@pytest.fixture(scope="module")
def artifacts(tmp_path_factory) -> Path:
    where = os.environ.get("EPHEM_TEST_ARTIFACTS")
    path = Path(where) if where else tmp_path_factory.mktemp("browser")
    path.mkdir(parents=True, exist_ok=True)
    return path


def _api(server: str, path: str):
    with urllib.request.urlopen(server + path, timeout=60) as r:
        body = r.read()
        return json.loads(body) if r.headers.get_content_type() == "application/json" else body.decode()


def _text(browser, element_id: str) -> str:
    from selenium.webdriver.common.by import By
    return browser.find_element(By.ID, element_id).text


def _click_and_wait(browser, element) -> None:
    """Click a link or a submit button and wait for the next page: WebDriver does not wait for a navigation a
    click starts, and a loaded machine answers a form (a batch, a track) in a second or more."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support import expected_conditions
    from selenium.webdriver.support.ui import WebDriverWait

    old = browser.find_element(By.TAG_NAME, "html")
    element.click()
    WebDriverWait(browser, 120).until(expected_conditions.staleness_of(old))
    WebDriverWait(browser, 120).until(lambda b: b.execute_script("return document.readyState") == "complete")


def _axe_violations(browser) -> list:
    source = AXE.read_bytes()
    assert hashlib.sha256(source).hexdigest() == AXE_SHA256, "the vendored axe-core is not the recorded one"
    browser.execute_script(source.decode("utf-8"))
    browser.set_script_timeout(60)
    result = browser.execute_async_script("const done = arguments[arguments.length - 1];"
                                          "axe.run(document).then(r => done(r.violations), e => done(String(e)));")
    assert isinstance(result, list), result
    return [{"id": v["id"], "help": v["help"], "nodes": [n["target"] for n in v["nodes"]][:3]} for v in result]


def test_from_the_catalogue_to_a_body_by_clicking(server, browser, artifacts):
    from selenium.webdriver.common.by import By

    browser.get(server + "/")
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "index.png"))
    _click_and_wait(browser, browser.find_element(By.LINK_TEXT, "Vesta"))
    assert urlsplit(browser.current_url).path == "/bodies/Vesta"
    want = _api(server, "/v1/bodies/vesta/precession")
    for key in ("precession_rate_arcsec_per_year", "obliquity_deg", "scaling_factor_arcsec_per_year"):
        assert float(_text(browser, key)) == pytest.approx(want[key], rel=5e-12), key
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "body.png"))


def test_the_track_form_submitted_gives_the_apis_track_and_reloads_to_it(server, browser, artifacts):
    from selenium.webdriver.common.by import By

    browser.get(server + "/bodies/ceres")
    for field, value in (("start", "2024-01-01"), ("stop", "2025-01-01"), ("step_days", "5"),
                         ("tolerance_mas", "1000")):
        box = browser.find_element(By.ID, field)
        box.clear()
        box.send_keys(value)
    _click_and_wait(browser, browser.find_element(By.CSS_SELECTOR, "form.track-form button[type=submit]"))
    query = parse_qs(urlsplit(browser.current_url).query)
    assert {k: query[k] for k in ("start", "stop", "step_days", "tolerance_mas")} == {
        "start": ["2024-01-01"], "stop": ["2025-01-01"], "step_days": ["5"], "tolerance_mas": ["1000"]}
    want = _api(server, "/v1/bodies/ceres/track?start=2024-01-01&stop=2025-01-01&step_days=5&tolerance_mas=1000")
    caption = browser.find_element(By.XPATH, "//table[contains(caption, 'track, the first')]/caption").text
    assert f"of {len(want['jd_tdb'])} epochs" in caption
    first_row = browser.find_elements(By.XPATH, "//table[contains(caption, 'track, the first')]/tbody/tr")[0]
    cells = [c.text for c in first_row.find_elements(By.XPATH, "./th|./td")]
    assert float(cells[-2]) == pytest.approx(want["pole_ra_deg"][0], rel=5e-10)     # 10 significant digits
    assert f"<strong>{want['model']['name']}</strong>" in browser.page_source
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "track.png"))
    # the permalink: the same URL, reloaded, is the same page
    url, shown = browser.current_url, caption
    browser.refresh()
    assert browser.current_url == url
    assert browser.find_element(By.XPATH, "//table[contains(caption, 'track, the first')]/caption").text == shown
    # the CSV download is the whole track
    href = browser.find_element(By.PARTIAL_LINK_TEXT, "Download the whole track").get_attribute("href")
    rows = _api(server, href.removeprefix(server)).strip().splitlines()
    assert len(rows) == len(want["jd_tdb"]) + 1                                     # the header and every epoch
    # the figure loaded (the browser decoded the API's PNG)
    img = browser.find_element(By.TAG_NAME, "img")
    assert browser.execute_script("return arguments[0].complete && arguments[0].naturalWidth", img) > 0


def test_an_error_stands_at_its_field(server, browser, artifacts):
    from selenium.webdriver.common.by import By

    browser.get(server + "/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=-1")
    problem = None
    try:
        _api(server, "/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=-1")
    except urllib.error.HTTPError as exc:
        problem = json.loads(exc.read())
    (err,) = problem["errors"]
    shown = browser.find_element(By.ID, f"{err['field']}-error")
    assert shown.is_displayed() and shown.text == err["reason"]
    assert browser.find_element(By.ID, err["field"]).get_attribute("aria-invalid") == "true"
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "error.png"))


def test_the_moons_page_is_accessible(server, browser, artifacts):
    browser.get(server + "/bodies/moon")
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "moon.png"))


def test_no_request_leaves_loopback(server, browser):
    """Everything the browser fetched for these pages (documents, the style sheet, the figures) came from the
    service on 127.0.0.1: Chromium's own network log, since the start of the browser."""
    browser.get(server + "/bodies/earth/track?start=2020-01-01&stop=2020-03-01&step_days=10")
    urls = []
    for entry in browser.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message.get("method") == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    assert urls, "no request logged"
    outside = [u for u in urls if not (u.startswith(server + "/") or u.startswith("data:") or u == "about:blank")]
    assert not outside, outside


def test_the_accessibility_check_can_fail(server, browser):
    """axe-core does run: an unlabelled input and an image without alt text added to a page are caught."""
    browser.get(server + "/")
    browser.execute_script("document.querySelector('main').insertAdjacentHTML('beforeend',"
                           " '<input name=\"x\"><img src=\"/static/page/page.css\">');")
    found = {v["id"] for v in _axe_violations(browser)}
    assert {"image-alt", "label"} <= found, found


def test_the_history_form_submitted_gives_the_apis_history(server, browser, artifacts):
    from selenium.webdriver.common.by import By

    browser.get(server + "/bodies/ceres")
    for field, value in (("history-start_year", "-20000"), ("history-stop_year", "0"), ("history-step_years", "500")):
        box = browser.find_element(By.ID, field)
        box.clear()
        box.send_keys(value)
    _click_and_wait(browser, browser.find_element(By.CSS_SELECTOR, "form.history-form button[type=submit]"))
    assert urlsplit(browser.current_url).path == "/bodies/Ceres/history"
    want = _api(server, "/v1/bodies/ceres/history?start_year=-20000&stop_year=0&step_years=500")
    caption = browser.find_element(By.XPATH, "//table[contains(caption, 'history, the first')]/caption").text
    assert f"of {len(want['year'])} epochs" in caption
    first_row = browser.find_elements(By.XPATH, "//table[contains(caption, 'history, the first')]/tbody/tr")[0]
    cells = [c.text for c in first_row.find_elements(By.XPATH, "./th|./td")]
    assert float(cells[1]) == pytest.approx(want["obliquity_deg"][0], rel=5e-8)      # 8 significant digits
    img = browser.find_element(By.TAG_NAME, "img")
    assert browser.execute_script("return arguments[0].complete && arguments[0].naturalWidth", img) > 0
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "history.png"))


def test_a_body_of_ones_own_submitted_in_the_browser(server, browser, artifacts):
    from selenium.webdriver.common.by import By

    from service.schemas import UserBody

    browser.get(server + "/")
    _click_and_wait(browser, browser.find_element(By.LINK_TEXT, "A body of your own"))
    box = browser.find_element(By.ID, "rotation_period_hours")
    box.clear()
    box.send_keys("6.5")
    _click_and_wait(browser, browser.find_element(By.CSS_SELECTOR, "form.my-body-form button[type=submit]"))
    user = {k: v for k, v in UserBody.model_config["json_schema_extra"]["examples"][0].items() if k != "track"}
    user["rotation_period_hours"] = 6.5
    request = urllib.request.Request(server + "/v1/precession-nutation", data=json.dumps(user).encode(),
                                     headers={"content-type": "application/json"})
    with urllib.request.urlopen(request, timeout=60) as r:
        want = json.load(r)["precession"]
    assert float(_text(browser, "precession_rate_arcsec_per_year")) == pytest.approx(
        want["precession_rate_arcsec_per_year"], rel=5e-12)
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "my_body.png"))


def test_a_batch_uploaded_in_the_browser(server, browser, artifacts, tmp_path):
    from selenium.webdriver.common.by import By

    from tests.service.test_pages import BATCH_CSV

    source = tmp_path / "bodies.csv"
    source.write_text(BATCH_CSV, encoding="utf-8")
    browser.get(server + "/")
    _click_and_wait(browser, browser.find_element(By.LINK_TEXT, "A batch"))
    browser.find_element(By.ID, "file").send_keys(str(source))
    _click_and_wait(browser, browser.find_element(By.CSS_SELECTOR, "form.batch-form button[type=submit]"))
    problems = [e.text for e in browser.find_elements(By.CSS_SELECTOR, ".problem")]
    assert not problems, problems
    caption = browser.find_element(By.XPATH, "//table/caption").text
    assert "of 3 answers" in caption
    href = browser.find_element(By.PARTIAL_LINK_TEXT, "Download the answers").get_attribute("href")
    assert href.startswith("data:text/csv") and "testb" in href
    assert not _axe_violations(browser)
    browser.save_screenshot(str(artifacts / "batch.png"))


def test_the_dataset_chooser_submitted(server, browser):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    browser.get(server + "/")
    Select(browser.find_element(By.ID, "dataset")).select_by_value("petit2014")
    _click_and_wait(browser, browser.find_element(By.CSS_SELECTOR, "main form button[type=submit]"))
    assert parse_qs(urlsplit(browser.current_url).query) == {"dataset": ["petit2014"]}
    names = {b["name"] for b in _api(server, "/v1/bodies?dataset=petit2014")}
    links = {a.text for a in browser.find_elements(By.XPATH, "//table//th[@scope='row']/a")}
    assert links == names


#: the phone of issue 41 (CSS px): the body and track pages were 1,035-1,141 px wide there
PHONE = {"width": 390, "height": 844, "deviceScaleFactor": 3, "mobile": True}
PHONE_PAGES = ("/bodies/vesta", "/bodies/earth", "/bodies/moon",
               "/bodies/earth/track?start=2000-01-01&stop=2030-01-01&step_days=3650&tolerance_mas=10"
               "&axis=forced_figure",
               "/bodies/ceres/history?start_year=-20000&stop_year=0&step_years=500", "/batch", "/my-body",
               "/docs/accuracy", "/about")


def test_a_phone_never_scrolls_sideways(server, browser, artifacts):
    """At 390 px the page is as wide as the screen: a wide table scrolls inside its own box (and on the body and
    track pages one does, so the check bites), a figure scales down (SVG), long words wrap."""
    browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", PHONE)
    try:
        for path in PHONE_PAGES:
            browser.get(server + path)
            width = browser.execute_script("return document.documentElement.clientWidth")
            scroll = browser.execute_script("return document.documentElement.scrollWidth")
            assert width <= PHONE["width"] and scroll <= PHONE["width"], (path, scroll, width)
            boxes = browser.execute_script(
                "return [...document.querySelectorAll('.table-scroll')].map(b => [b.scrollWidth, b.clientWidth])")
            if path.startswith("/bodies/") and "/history" not in path:
                assert any(s > c for s, c in boxes), (path, boxes)     # a table wider than the phone, boxed
            for img in browser.find_elements("css selector", "figure img"):
                shown = browser.execute_script("const r = arguments[0].getBoundingClientRect(); "
                                               "return [r.width, arguments[0].naturalWidth, arguments[0].currentSrc]",
                                               img)
                assert 0 < shown[0] <= width and shown[1] > 0, (path, shown)   # loaded, and scaled to the page
                assert ".svg" in shown[2], (path, shown)
            browser.save_screenshot(str(artifacts / f"phone_{path.strip('/').split('?')[0].replace('/', '_')}.png"))
    finally:
        browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})


def test_the_docs_and_redoc_load_nothing_from_outside(server, browser):
    """The accuracy document renders with its six charts (each decoded by the browser), and ReDoc's page, which
    fetched Redocly's logo from a CDN, reaches nothing but the service (Chromium's network log)."""
    from selenium.webdriver.common.by import By

    browser.get_log("performance")                        # drop what came before
    browser.get(server + "/docs/accuracy")
    charts = browser.find_elements(By.CSS_SELECTOR, "img[src^='/docs/charts/']")
    assert len(charts) == 6
    from selenium.webdriver.support.ui import WebDriverWait
    WebDriverWait(browser, 60).until(lambda b: all(b.execute_script(
        "return arguments[0].complete && arguments[0].naturalWidth > 0", i) for i in charts))
    assert not _axe_violations(browser)
    browser.get(server + "/about")                       # the sources' table, the BibTeX, the theories
    assert not _axe_violations(browser)
    browser.get(server + "/redoc")
    # the menu, whose foot held the logo, mounted and drawn: "API docs by Redocly" is its last line
    WebDriverWait(browser, 120).until(lambda b: "API docs by Redocly" in b.find_element(By.TAG_NAME, "body").text)
    urls = []
    for entry in browser.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message.get("method") == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    assert any(u.endswith("/redoc/redoc.standalone.js") for u in urls), urls
    # ReDoc's search worker is a blob of the service's own origin
    outside = [u for u in urls if not (u.startswith((server + "/", f"blob:{server}/", "data:")) or u == "about:blank")]
    assert not outside, outside
