"""The explorer (``bifurc explore``, ``ds.bifurc.explore()``) on a small stored diagram of the main job's scene:
served and driven in headless Chromium (hover a value, click it), executed as a notebook, its refusals in one line,
its problem rebuilt from the stored attributes; a census' and a regime map's pages clicked in the browser.

The truths are the stored diagram's own labels, computed by the sweep before the explorer exists: the hovered
class text is the stored class's, and a periodic value's re-simulated time history over a whole number j of its
periods holds exactly j times its stored impacts per period.
"""
from __future__ import annotations

import contextlib
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import bifurc
from bifurc.cli import main
from bifurc.labels.classify import describe

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM, DRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
#: where the how-to page's screenshot is written when BIFURC_SCREENSHOTS=1 (docs/how-to/explore.md)
SCREENSHOT = ROOT / "docs" / "images" / "explore.png"
VALUES = [8.3, 8.5, 8.6]
CLICKED = 8.5

panel = pytest.importorskip("panel", reason="the explore extra (panel) is not installed")


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    """A 3-value diagram of the README's main job around 8.5 Hz (300 + 100 relay periods, no extension)."""
    path = tmp_path_factory.mktemp("explore") / "diagram.nc"
    pb = __import__("maps").problem("thesis-1dof", preset="matlab-listing", params={"V": 90})
    bifurc.sweep(pb, "relay_hz", np.array(VALUES), bifurc.Diagram(transient=300, record=100, budget=400,
                                                                  error_sample=0),
                 run=bifurc.Run(workers=1, progress=False, path=str(path)))
    return path


def _expected(ds, value):
    d = ds.isel(branch=0).sel(relay_hz=value)
    return int(d.class_code), int(d.period), int(d.impacts_per_period)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _history_numbers(text: str) -> tuple[int, int]:
    m = re.search(r"over (\d+) relay periods after the record: \**(\d+) impacts", text)
    assert m, text
    return int(m.group(1)), int(m.group(2))


def _check_history(ds, text: str) -> None:
    """The time history's impact count: j periods of a period-n orbit with m impacts each hold j m / n impacts."""
    code, n, m = _expected(ds, CLICKED)
    assert code == 0 and n > 0, "the stored value is periodic"
    periods, impacts = _history_numbers(text)
    assert periods % n == 0 and periods >= n
    assert impacts == m * periods // n


# ----- the page in a real browser ---------------------------------------------------------------------------
#: every shadow root's visible text (Bokeh and Panel draw inside shadow DOM)
TEXT_JS = """
function walk(root, out) { for (const el of root.querySelectorAll('*')) { if (el.shadowRoot) walk(el.shadowRoot, out); }
  out.push(root); return out; }
return walk(document, []).map(r => r === document ? document.body.innerText :
  [...r.children].filter(c => !['STYLE', 'LINK', 'SCRIPT'].includes(c.tagName)).map(c => c.innerText || '').join(' '))
  .join(' | ');"""
#: the viewport pixel of a parameter value at the middle height of a named figure's frame
PIXEL_JS = """
function find(v, id) { if (v.model && v.model.id === id) return v;
  for (const c of (v.child_views ? [...v.child_views] : [])) { const r = find(c, id); if (r) return r; } return null; }
const f = Bokeh.documents[0].get_model_by_name(arguments[0]);
let view = null; for (const k of Object.keys(Bokeh.index)) { view = find(Bokeh.index[k], f.id); if (view) break; }
if (!view) return null;
const r = view.canvas_view.el.getBoundingClientRect();
return [r.x + view.frame.x_scale.compute(arguments[1]),
        r.y + (arguments[2] === undefined ? view.frame.bbox.vcenter : view.frame.y_scale.compute(arguments[2]))];"""
#: click the first button whose label is arguments[0] (Panel draws its widgets inside shadow DOM)
BUTTON_JS = """
const label = arguments[0];
function walk(root) { for (const el of root.querySelectorAll('*')) {
    if (el.tagName === 'BUTTON' && el.innerText.trim() === label && !el.disabled) { el.click(); return true; }
    if (el.shadowRoot) { const r = walk(el.shadowRoot); if (r) return r; } } return false; }
return walk(document);"""


#: a named figure's hover columns (the census': one per value) or cells (the map's): their values and texts
COLUMNS_JS = """
const f = Bokeh.documents[0].get_model_by_name(arguments[0]);
for (const r of f.renderers) { const d = r.data_source.data;
  if (d.value && d.text) return {value: Array.from(d.value), value2: d.value2 ? Array.from(d.value2) : null,
                                 text: Array.from(d.text)}; }
return null;"""
#: the census page's basin fraction bars: value, bottom, top
BARS_JS = """
const d = Bokeh.documents[0].get_model_by_name('fractions').renderers[0].data_source.data;
return {p: Array.from(d.p), bottom: Array.from(d.bottom), top: Array.from(d.top)};"""
#: set a named figure's x range (and its y range when given), as the toolbar's box zoom does
RANGE_JS = """
const f = Bokeh.documents[0].get_model_by_name(arguments[0]);
f.x_range.start = arguments[1]; f.x_range.end = arguments[2];
if (arguments.length > 3) { f.y_range.start = arguments[3]; f.y_range.end = arguments[4]; }"""


def _browser():
    """A headless Chromium driven by selenium, or a skip with the one-line reason."""
    if not (CHROMIUM.exists() and DRIVER.exists()):
        pytest.skip("no browser: /usr/bin/chromium and /usr/bin/chromedriver (apt-get install chromium chromium-driver)")
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (the test extra)")
    from selenium.webdriver.chrome.service import Service
    import tempfile
    opts = webdriver.ChromeOptions()
    opts.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 f"--user-data-dir={tempfile.mkdtemp(prefix='bifurc-chromium-')}", "--window-size=1400,1500"):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(str(DRIVER)), options=opts)


def _wait(predicate, seconds: float, what: str):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.25)
    raise AssertionError(f"waited {seconds:g} s for {what}")


def _move(driver, xy, click=False):
    from selenium.webdriver.common.actions.action_builder import ActionBuilder
    ab = ActionBuilder(driver)
    ab.pointer_action.move_to_location(int(xy[0]), int(xy[1]))
    if click:
        ab.pointer_action.click()
    ab.perform()


@pytest.fixture(scope="module")
def chromium():
    """One headless Chromium for the module's pages."""
    driver = _browser()
    yield driver
    driver.quit()


@contextlib.contextmanager
def _served(path, driver):
    """``bifurc explore path`` served on a free loopback port, and the headless Chromium ``driver`` on its page
    (the page's figures drawn); at the end, no severe message in the browser's console."""
    driver.get_log("browser")                                  # a former page's messages are not this one's
    port = _free_port()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    server = subprocess.Popen([sys.executable, "-m", "bifurc", "explore", str(path), "--port", str(port),
                               "--no-browser"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        def up():
            try:
                socket.create_connection(("127.0.0.1", port), 1).close()
                return True
            except OSError:
                assert server.poll() is None, server.stderr.read().decode()
                return False
        _wait(up, 60, "the server")
        driver.get(f"http://127.0.0.1:{port}/")
        _wait(lambda: driver.execute_script("return window.Bokeh && Bokeh.documents.length ? 1 : 0"), 30, "the page")
        yield driver
        severe = [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert not severe, severe
    finally:
        driver.get("about:blank")
        server.terminate()
        server.wait(timeout=30)


def _text(driver):
    return driver.execute_script(TEXT_JS)


def _screenshot(driver, tmp_path, name: str) -> None:
    """A screenshot of the page; copied to docs/images/ when BIFURC_SCREENSHOTS=1 (the how-to page's pictures)."""
    driver.save_screenshot(str(tmp_path / name))
    assert (tmp_path / name).stat().st_size > 10_000
    if os.environ.get("BIFURC_SCREENSHOTS") == "1":
        shutil.copy(tmp_path / name, SCREENSHOT.parent / name)


def test_served_page_hover_shows_the_stored_class_and_a_click_its_history_and_orbit(stored, chromium, tmp_path):
    ds = bifurc.load(stored)
    code, n, m = _expected(ds, CLICKED)
    with _served(stored, chromium) as driver:
        xy = _wait(lambda: driver.execute_script(PIXEL_JS, "diagram", CLICKED), 30, "the diagram drawn")
        _move(driver, xy)
        hovered = describe(code, n, m)                   # "period-17, 12 impacts (17:12)"
        text = _wait(lambda: (t := _text(driver)) and hovered in t and t, 30, "the hover tooltip")
        assert re.search(rf"class:\s*{re.escape(hovered)}", text)
        _move(driver, xy, click=True)
        text = _wait(lambda: (t := _text(driver)) and "after the record" in t and
                     "Periodic orbit" in t and t, 90, "the time history and the orbit")
        _check_history(ds, text)
        assert re.search(rf"Periodic orbit: period {n}, {m} impacts per period, stable", text)
        # its Floquet multipliers, one per state (4), all inside the unit circle as a stable orbit's are
        mus = re.search(r"Floquet multipliers \|mu\| = ([^;]*);", text)
        moduli = [float(x) for x in re.findall(r"([\d.e+-]+) \(arg", mus.group(1))] if mus else []
        assert len(moduli) == 4 and max(moduli) < 1, mus and mus.group(1)
        _screenshot(driver, tmp_path, "explore.png")
        # the branch button, pressed in the browser: relay_hz sets the relay period under mains forcing, so its
        # continuation is refused, in one line on the status line
        assert _wait(lambda: driver.execute_script(BUTTON_JS, "Continue branch"), 30, "the branch button enabled")
        text = _wait(lambda: (t := _text(driver)) and "no branch:" in t and t, 60, "the branch's answer")
        assert re.search(r"no branch: [^|]*relay_hz", text)
        # a zoom, as the toolbar's box zoom sets the range: once the view rests, 200 values are swept anew and the
        # status line counts them from the first chunk
        driver.execute_script("const r = Bokeh.documents[0].get_model_by_name('diagram').x_range; "
                              "r.start = 8.45; r.end = 8.55;")
        text = _wait(lambda: (t := _text(driver)) and re.search(r"zoom 8.45 to 8.55, first picture: [1-9]\d* of 200", t)
                     and t, 90, "the zoom's progress")


OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=1.3, e=-1.0, r=0.8)


@pytest.fixture(scope="module")
def census(tmp_path_factory):
    """A census of the impact oscillator at two values of Omega, 36 fresh starts on a 6 x 6 slice of (x, v)."""
    path = tmp_path_factory.mktemp("census") / "census.nc"
    bifurc.attractors("impact-oscillator", "Omega", [1.25, 1.3], params=OSC, box={"x": (-1.0, 2.0), "v": (-2.0, 2.0)},
                      starts="slice", shape=(6, 6), progress=False, workers=1, link=False, path=str(path))
    return path


def test_served_census_click_shows_each_attractor_its_fraction_and_a_history_and_a_zoom_repaints_it(census, chromium, tmp_path):
    """Click Omega = 1.3 of a census in the browser: each attractor's class and basin fraction (its starts' count
    over 36, counted here from where each start went) with its interval, and the largest basin's time history,
    whose impacts are j m / n over j periods of a period-n orbit with m impacts; then a zoom on 1.25 to 1.28
    repaints the figure with 20 values, each value's basin fractions whole numbers of its 25 starts summing to one."""
    ds = bifurc.load(census)
    i = 1
    went = ds.start_attractor.values[i]
    labels = [str(x) for x in ds.attractor_label.values]
    present = [j for j in range(len(labels)) if labels[j].startswith("A") and (went == j).any()]
    assert len(present) == 2, "the oscillator is bistable at Omega = 1.3"
    from bifurc.attractors.dataset import attractor_text
    with _served(census, chromium) as driver:
        xy = _wait(lambda: driver.execute_script(PIXEL_JS, "census", 1.3), 30, "the census drawn")
        _move(driver, xy, click=True)
        text = _wait(lambda: (t := _text(driver)) and "from its stored strobe state" in t and t, 90,
                     "the attractors and a time history")
        for j in present:
            share = (went == j).sum() / went.size
            row = rf"{labels[j]}\s*\|?\s*{re.escape(attractor_text(ds, i, j))}\s*\|?\s*{share:.3f} \["
            assert re.search(row, text), (row, text[:2000])
        top = max(present, key=lambda j: (went == j).sum())
        n, m = int(ds.period.values[i, top]), int(ds.impacts_per_period.values[i, top])
        got = re.search(rf"{labels[top]} at Omega = 1.3: [^.]*\.\** Time history over (\d+) periods from its stored "
                        rf"strobe state: \**(\d+) impacts", text)
        assert got, text[:2000]
        periods, impacts = int(got.group(1)), int(got.group(2))
        assert periods % n == 0 and impacts == m * periods // n
        _screenshot(driver, tmp_path, "explore-census.png")
        # a zoom, as the toolbar's box zoom sets the range: once the view rests, the census is computed anew on 20
        # values of 1.25 to 1.28 with 25 of the slice's starts (5 x 5; the stored census had 36), the status line
        # counting the values, and the figure repainted with them
        from bifurc.explore.compute import ZOOM_CENSUS_VALUES, ZOOM_STARTS
        assert (ZOOM_CENSUS_VALUES, ZOOM_STARTS) == (20, 25)
        driver.execute_script(RANGE_JS, "census", 1.25, 1.28)
        _wait(lambda: re.search(r"zoom 1.25 to 1.28, census: \d+ of 20 values \([\d.]+ s\); 25 starts per value "
                                r"\(the stored census had 36\)", _text(driver)), 60, "the census zoom's progress")
        _wait(lambda: "zoom 1.25 to 1.28: census shown" in _text(driver), 120, "the census zoom's end")
        cols = _wait(lambda: (c := driver.execute_script(COLUMNS_JS, "census")) and len(c["value"]) == 20 and c, 30,
                     "the census repainted with the zoom's 20 values")
        assert np.allclose(cols["value"], np.linspace(1.25, 1.28, 20), rtol=0, atol=1e-12)
        # each value's basin fractions: whole numbers of starts out of 25, summing to one
        bars = driver.execute_script(BARS_JS)
        p, height = np.asarray(bars["p"]), np.asarray(bars["top"]) - np.asarray(bars["bottom"])
        assert np.allclose(np.sort(np.unique(p)), cols["value"])
        assert np.allclose(height * 25, np.round(height * 25), atol=1e-9)
        for v in cols["value"]:
            assert abs(height[np.isclose(p, v)].sum() - 1) < 1e-9
        r = driver.execute_script("const r = Bokeh.documents[0].get_model_by_name('census').x_range; "
                                  "return [r.start, r.end];")
        step = 0.03 / 19
        assert np.allclose(r, [1.25 - step, 1.28 + step])            # the view on the zoomed values
        _screenshot(driver, tmp_path, "explore-census-zoom.png")


@pytest.fixture(scope="module")
def regime(tmp_path_factory):
    """A 2 x 2 regime map of the impact oscillator over Omega and the restitution r."""
    path = tmp_path_factory.mktemp("map") / "map.nc"
    bifurc.regime_map("impact-oscillator", "Omega", [1.25, 1.3], "r", [0.7, 0.8], params=OSC, transient=100,
                      record=50, budget=150, error_sample=0, workers=1, progress=False, path=str(path))
    return path


def test_served_map_click_shows_the_cells_class_history_and_orbit_and_a_zoom_repaints_it(regime, chromium, tmp_path):
    """Click the cell (1.25, 0.8) in the browser: its stored class (the map's, computed before), a time history
    with j m / n impacts over j periods, and its periodic orbit with the same period and impacts; then a zoom on a
    rectangle repaints the map with 12 x 12 cells, the one at the stored cell's values with the stored class."""
    ds = bifurc.load(regime)
    c = ds.sel(Omega=1.25, r=0.8)
    code, n, m = int(c.class_code), int(c.period), int(c.impacts_per_period)
    assert code == 0 and n >= 1 and m >= 1, "a periodic cell with impacts"
    with _served(regime, chromium) as driver:
        xy = _wait(lambda: driver.execute_script(PIXEL_JS, "map", 1.25, 0.8), 30, "the map drawn")
        _move(driver, xy)
        text = _wait(lambda: (t := _text(driver)) and describe(code, n, m) in t and t, 30, "the hover tooltip")
        _move(driver, xy, click=True)
        text = _wait(lambda: (t := _text(driver)) and "after the cell's record" in t and "Periodic orbit" in t and t,
                     90, "the cell's history and orbit")
        assert f"Omega = 1.25, r = 0.8: {describe(code, n, m)}" in text
        got = re.search(r"over (\d+) periods after the cell's record: \**(\d+) impacts", text)
        periods, impacts = int(got.group(1)), int(got.group(2))
        assert periods % n == 0 and impacts == m * periods // n
        assert re.search(rf"Periodic orbit: period {n}, {m} impacts? per period", text)
        _screenshot(driver, tmp_path, "explore-map.png")
        # a zoom on the rectangle Omega 1.25 to 1.28 by r 0.74 to 0.8: computed anew on 12 x 12 cells with the map's
        # settings, the status line counting the cells; its corner (1.25, 0.8) is the stored cell's very value and
        # settings (every cell starts from the same state), so it gets the stored class
        from bifurc.explore.compute import ZOOM_MAP_SIDE
        assert ZOOM_MAP_SIDE == 12
        driver.execute_script(RANGE_JS, "map", 1.25, 1.28, 0.74, 0.8)
        _wait(lambda: re.search(r"zoom Omega 1.25 to 1.28, r 0.74 to 0.8, first picture: \d+ of 144 cells",
                                _text(driver)), 60, "the map zoom's progress")
        _wait(lambda: re.search(r"zoom Omega 1.25 to 1.28, r 0.74 to 0.8, anytime labels: \d+ of 144 cells|"
                                r"zoom Omega 1.25 to 1.28, r 0.74 to 0.8: anytime labels shown", _text(driver)), 120,
              "the map zoom's first picture")
        cells = _wait(lambda: (c := driver.execute_script(COLUMNS_JS, "map")) and len(c["value"]) == 144 and c, 30,
                      "the map repainted with the zoom's 144 cells")
        v1, v2 = np.asarray(cells["value"]), np.asarray(cells["value2"])
        assert np.allclose(np.unique(v1), np.linspace(1.25, 1.28, 12)) and np.allclose(np.unique(v2),
                                                                                       np.linspace(0.74, 0.8, 12))
        corner = int(np.argmin(np.abs(v1 - 1.25) + np.abs(v2 - 0.8)))
        assert cells["text"][corner] == describe(code, n, m)
        _screenshot(driver, tmp_path, "explore-map-zoom.png")


# ----- the notebook form --------------------------------------------------------------------------------------
def test_the_notebook_form_executes_and_its_widgets_hold_the_clicked_value(stored, tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    ds = bifurc.load(stored)
    code, n, m = _expected(ds, CLICKED)
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(f"import bifurc\nds = bifurc.load({str(stored)!r})\nex = ds.bifurc.explore()\nex"),
                nbformat.v4.new_code_cell(f"ex.select({CLICKED}, wait=True)\nprint(ex.history_text)\n"
                                          f"print(ex.orbit_text)\nprint('multipliers', len(ex.multiplier_source.data['re']))\n"
                                          f"print('button', ex.branch_button.disabled)\nex.close()")]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    before = dict(os.environ)
    os.environ.update(env)
    try:
        nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                resources={"metadata": {"path": str(tmp_path)}}).execute()
    finally:
        os.environ.clear()
        os.environ.update(before)
    outputs = [o for c in nb.cells for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.output_type == "error"]
    shown = nb.cells[0].outputs[-1].get("data", {})
    assert "application/vnd.holoviews_exec.v0+json" in shown or "text/html" in shown, list(shown)
    text = "".join(o.get("text", "") for o in nb.cells[1].outputs)
    _check_history(ds, text)
    assert f"period {n}, {m} impacts per period" in text
    assert "multipliers 4" in text and "button False" in text    # 4 states: 4 multipliers; a periodic value


# ----- refusals and the rebuilt problem -------------------------------------------------------------------------
def test_bad_input_is_refused_in_one_line(stored, tmp_path, capsys):
    port = _free_port()
    history = tmp_path / "run.nc"
    bifurc.load  # noqa: B018 - the same loader the command uses
    assert main(["simulate", "--relay-hz", "9", "--periods", "1", "-o", str(history)]) == 0
    capsys.readouterr()
    cases = [([str(tmp_path / "none.nc")], "no dataset at"),
             ([str(history)], "holds a history dataset"),
             ([str(stored), "--port", "80"], "--port 80: allowed 1024 to 65535"),
             ([str(stored), "--port", "70000"], "--port 70000: allowed 1024 to 65535")]
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", port))
        busy.listen()
        cases.append(([str(stored), "--port", str(port)], f"--port {port}: in use on 127.0.0.1"))
        for argv, words in cases:
            assert main(["explore", *argv, "--no-browser"]) == 2, argv
            err = capsys.readouterr().err
            assert err.count("\n") == 1 and err.startswith("bifurc: error:") and words in err, err


def test_the_problem_is_rebuilt_from_the_stored_attributes(stored):
    """The rebuilt problem reproduces a stored strobe point: one relay period from a stored sample."""
    import maps
    from bifurc.explore.compute import problem_of
    ds = bifurc.load(stored)
    pb = problem_of(ds).with_values(relay_hz=CLICKED)
    assert pb.options.dc_law == "listing" and pb.values["V"] == 90 and pb.preset == "matlab-listing"
    d = ds.isel(branch=0).sel(relay_hz=CLICKED)
    start, k = bifurc.sweep_point(ds, CLICKED, sample=0)
    smap = maps.StroboscopicMap(pb, tol=float(ds.attrs["tol"]))
    nxt = smap.step(start, k)
    after = nxt[0] if isinstance(nxt, tuple) else nxt
    stored_next = np.array([float(d[s].values[1]) for s in pb.system.state_names])
    assert np.allclose(after.y, stored_next, rtol=1e-6, atol=1e-8)


def test_a_branch_passes_through_the_stored_strobe_points_of_the_diagram(tmp_path):
    """The impact oscillator's period-1 branch through e = 0.15, continued to both ends of a diagram over e: at
    each stored periodic value it meets, its strobe point is the stored one (the sweep's, computed before)."""
    from bifurc.explore.app import Explorer
    path = tmp_path / "osc.nc"
    bifurc.sweep("impact-oscillator", "e", np.linspace(0.0, 0.3, 7), bifurc.Diagram(transient=100, record=50,
                                                                                     budget=150, error_sample=0),
                 run=bifurc.Run(workers=1, progress=False, path=str(path)))
    ds = bifurc.load(path)
    ex = Explorer(ds, zoom=False)
    try:
        ex.select(0.15, wait=True)
        assert not ex.branch_button.disabled
        ex.continue_branch(wait=True)
        p, y = np.asarray(ex.branch_source.data["p"]), np.asarray(ex.branch_source.data["y"])
        assert p.size >= 10 and p.min() <= 0.0 + 1e-9 and p.max() >= 0.3 - 1e-9     # both ends reached
        d = ds.isel(branch=0)
        for e in d.e.values:
            sub = d.sel(e=e)
            if int(sub.class_code) != 0 or int(sub.period) != 1:
                continue
            stored = sub.x.values[np.isfinite(sub.x.values)]
            assert np.ptp(stored) < 1e-6                        # a period-1 orbit: one strobe point
            order = np.argsort(p)
            on_branch = np.interp(e, p[order], y[order]) / ex._y        # the page's y is in mm
            assert abs(on_branch - stored[0]) < 1e-3 * max(0.1, abs(stored[0])), (e, on_branch, stored[0])
        assert "points in" in ex.status
    finally:
        ex.close()


def test_relay_frequency_has_no_branch_and_says_so_in_one_line(stored):
    from bifurc.explore.compute import Computer
    r = Computer(bifurc.load(stored)).branch(CLICKED, max_points=5)
    assert r["branches"] == [] and "relay_hz" in r["error"] and "\n" not in r["error"]


def test_a_zoom_streams_its_chunks_and_labels_the_stored_value_alike(stored):
    """Six values up to 8.5 Hz in two warm zoom processes (chunks of 4): the picture grows chunk by chunk, both
    stages finish, every value is there once in order, and 8.5 Hz gets the stored class and the stored strobe
    points at each stage (the stored diagram was swept with the same transient, record and budget)."""
    from bifurc.explore.compute import ZOOM_CHUNK, Computer, Spares, Zoom
    ds = bifurc.load(stored)
    c = Computer(ds)
    spares = Spares(c, workers=2).fill()
    values = np.linspace(8.4, 8.5, 6)                       # two chunks: 4 and 2 values
    z = Zoom(c, 8.4, 8.5, 6, workers=2, spares=spares)
    assert len(z.children) == 2 and not spares.children  # both taken
    sizes, at_stage = [], {}
    try:
        end = time.monotonic() + 240
        while time.monotonic() < end:
            s = z.poll()
            assert not s["error"], s["error"]
            if s["dataset"] is not None:
                sizes.append(s["dataset"].sizes["relay_hz"])
                at_stage.setdefault(s["stage"], s["dataset"])
            if s["stage"] >= 2:
                break
            time.sleep(0.1)
    finally:
        z.close()
        spares.close()
    assert not z.folder.exists() and not spares.dir.exists()
    assert ZOOM_CHUNK == 4 and sizes[0] in (2, 4, 6) and sizes[-1] == 6 and 1 in at_stage and 2 in at_stage
    code, n, m = _expected(ds, CLICKED)
    for stage in (1, 2):
        zd = at_stage[stage]
        assert np.allclose(zd.relay_hz.values, values)
        got = zd.isel(branch=0).sel(relay_hz=CLICKED)
        assert (int(got.class_code), int(got.period), int(got.impacts_per_period)) == (code, n, m)
        stored_x = ds.isel(branch=0).sel(relay_hz=CLICKED).x.values
        assert np.allclose(got.x.values, stored_x, rtol=1e-9, atol=1e-12, equal_nan=True)


def test_a_zooms_first_picture_is_a_plain_sweep_of_the_same_values(stored):
    """40 values in two warm zoom processes, whose first picture sweeps groups of up to 6 chunks of 4 values in one
    call each (claimed in turn, :func:`zoom_groups`), split back into chunks: every value's class, period, impacts
    and strobe points are those of one plain sweep of the 40 values at the same 300 + 100 periods without
    extension, exponent or grazing search (the batch engine's lanes are independent, so a value's batch-mates do
    not change it)."""
    from bifurc.explore.compute import ZOOM_CHUNK, ZOOM_GROUP, Computer, Spares, Zoom, zoom_groups
    groups = zoom_groups(10, 2, ZOOM_GROUP)
    assert groups == [(0, 1), (1, 2), (2, 4), (4, 6), (6, 7), (7, 8), (8, 9), (9, 10)]   # ceil(r / 4), r left
    assert zoom_groups(50, 2, 6)[:4] == [(0, 1), (1, 2), (2, 8), (8, 14)] and zoom_groups(50, 2, 6)[-1] == (49, 50)
    c = Computer(bifurc.load(stored))
    spares = Spares(c, workers=2).fill()
    z = Zoom(c, 8.0, 8.5, 40, workers=2, spares=spares)
    try:
        end = time.monotonic() + 240
        while time.monotonic() < end:
            s = z.poll()
            assert not s["error"], s["error"]
            if s["stage"] >= 1:
                break
            time.sleep(0.1)
        got = z.picture()
        assert s["stage"] >= 1 and len(z.chunks) == 40 // ZOOM_CHUNK
    finally:
        z.close()
        spares.close()
    pb = __import__("maps").problem("thesis-1dof", preset="matlab-listing", params={"V": 90})
    values = np.linspace(8.0, 8.5, 40)                      # 8.5 Hz periodic (period 17), the rest not yet
    plain = bifurc.sweep(pb, "relay_hz", values, bifurc.Diagram(transient=300, record=100, budget=400, lyapunov=False,
                                                                grazing=False, error_sample=0),
                         run=bifurc.Run(workers=1, progress=False)).isel(branch=0)
    got = got.isel(branch=0)
    assert np.array_equal(got.relay_hz.values, values)
    for name in ("class_code", "period", "impacts_per_period"):
        assert np.array_equal(got[name].values, plain[name].values), name
    assert len(set(plain.class_code.values.tolist())) > 1          # more than one class in the range
    assert np.allclose(got.x.values, plain.x.values, rtol=1e-12, atol=1e-15, equal_nan=True)
    assert "impact" not in got.dims                                # not drawn: dropped before the pickle


def test_a_newer_click_makes_the_older_one_stale(stored):
    """Two clicks in a row: the page shows the second value only (the first's result, if it ran, is dropped)."""
    from bifurc.explore.app import Explorer
    ds = bifurc.load(stored)
    ex = Explorer(ds, zoom=False)
    try:
        ex.select(8.3)
        ex.select(CLICKED, wait=True)
        _check_history(ds, ex.history_text)
        assert ex.history_text.startswith(f"**relay_hz = {CLICKED:g} Hz")
        assert not ex._pending or all(f.done() for _, _, f, _ in ex._pending)
    finally:
        ex.close()


def test_a_zoom_repaints_the_page_from_its_first_chunk_and_its_values_are_clicked_alike(stored):
    """The page's zoom (Explorer.zoom, 6 values to 8.5 Hz): the diagram is repainted as chunks land (a part of the
    values first, all at the end), the view stays on the zoomed range, and 8.5 Hz of the zoom, clicked, shows the
    stored value's impacts (the stored diagram is the truth: same transient, record and budget)."""
    from bifurc.explore.app import Explorer
    ds = bifurc.load(stored)
    ex = Explorer(ds, zoom=False)
    try:
        ex.zoom(8.4, 8.5, 6)
        painted, end = [], time.monotonic() + 240
        while time.monotonic() < end and "anytime labels shown" not in ex.status:
            ex._poll()
            n = len(ex.columns.data["value"])
            if ex.computer is not ex.stored_computer and (not painted or painted[-1] != n):
                painted.append(n)
                r = ex.diagram_figure.x_range
                assert np.isclose(r.start, 8.38) and np.isclose(r.end, 8.52), (r.start, r.end)
            assert not ex.status.startswith("zoom failed"), ex.status
            time.sleep(0.1)
        assert "anytime labels shown" in ex.status, ex.status
        # chunks of 4 and 2 values: the first repaint shows one of them, or both when they landed between two polls
        assert painted[0] in (2, 4, 6) and painted[-1] == 6, painted
        ex.select(CLICKED, wait=True)
        _check_history(ds, ex.history_text)
    finally:
        ex.close()


def test_map_and_census_refusals_are_one_line(regime, census, tmp_path):
    from bifurc.explore.app import explorer_of
    from bifurc.explore.compute import CensusComputer, MapComputer
    from maps.parameters import ParameterError
    with pytest.raises(ParameterError, match=r"^Omega = 9: outside the map's 1.25 to 1.3$"):
        MapComputer(bifurc.load(regime)).index(9.0, 0.8)
    with pytest.raises(ParameterError, match=r"^Omega = 2: outside the census' 1.25 to 1.3$"):
        CensusComputer(bifurc.load(census)).attractors(2.0)
    with pytest.raises(ParameterError, match=r"^attractor 'A7': not an attractor present at Omega = 1.3$"):
        CensusComputer(bifurc.load(census)).history(1.3, "A7")
    h = __import__("maps").simulate("impact-oscillator", periods=1)
    with pytest.raises(ParameterError, match=r"needs a diagram, map or attractors dataset.*this is a history dataset$"):
        explorer_of(h)
    # a zoom beyond a parameter's allowed range (the restitution r <= 1): refused in one line before any process
    # starts, from Python and on the page's status line when a resting view asks for it
    from bifurc.explore.compute import Zoom
    with pytest.raises(ParameterError, match=r"^parameter 'r' \(coefficient of restitution\) = 1.2 is outside its "
                                             r"allowed range \[0, 1\]$"):
        Zoom(MapComputer(bifurc.load(regime)), 1.26, 1.29, 3, second=(0.9, 1.2, 3))
    ex = explorer_of(bifurc.load(regime))
    try:
        ex._range_seen = (((1.26, 1.29), (0.9, 1.2)), time.monotonic() - 10)
        ex._poll()
        assert ex._zoom is None and ex.status.startswith("zoom refused: parameter 'r'") and "\n" not in ex.status
    finally:
        ex.close()


def test_a_census_zooms_chunks_join_with_each_start_at_its_attractor(census):
    """Two censuses of consecutive values (a census zoom's chunks) joined as one: the values in order, each part's
    attractors kept apart, and at every value each attractor's basin fraction is the share of the fresh starts
    that the joined dataset says reached it (the starts renumbered with the attractors), its class the part's."""
    from bifurc.explore.compute import CensusComputer, join_censuses, zoom_starts
    ds = bifurc.load(census)
    kw = dict(params=OSC, box={"x": (-1.0, 2.0), "v": (-2.0, 2.0)}, starts="slice", shape=(3, 3), progress=False,
              workers=1, link=False)
    parts = [bifurc.attractors("impact-oscillator", "Omega", v, **kw) for v in ([1.25, 1.27], [1.29, 1.3])]
    joined = join_censuses(parts)
    assert np.allclose(joined.Omega.values, [1.25, 1.27, 1.29, 1.3])
    labels = [str(x) for x in joined.attractor_label.values]
    ids = [sum(str(x).startswith("A") for x in p.attractor_label.values) for p in parts]
    assert labels[:sum(ids)] == [f"A{k}" for k in range(sum(ids))]
    for i in range(4):
        went = joined.start_attractor.values[i]
        assert went.size == 9
        for j in range(len(labels)):
            assert abs(joined.basin_fraction.values[i, j] - (went == j).mean()) < 1e-12 or \
                (np.isnan(joined.basin_fraction.values[i, j]) and not (went == j).any())
        p, k = parts[i // 2], i % 2
        offset = 0 if i < 2 else ids[0]
        for j in range(ids[i // 2]):
            assert joined.class_code.values[i, offset + j] == p.class_code.values[k, j]
    rows = CensusComputer(ds).on(joined).attractors(1.29)["rows"]
    assert abs(sum(r["fraction"] for r in rows) - 1) < 1e-12
    # the zoom's starts: the stored slice's kind and box with at most 25 of them, the sides scaled alike
    spec, n, stored = zoom_starts(ds, ["x", "v"])
    assert spec == {"kind": "slice", "shape": [5, 5], "box": {"x": [-1.0, 2.0], "v": [-2.0, 2.0]}} and \
        (n, stored) == (25, 36)
    boxed = ds.assign_attrs(starts_sampler="Box(n=200, box=None, seed=7)", fresh_starts=200)
    assert zoom_starts(boxed, ["x", "v"])[0] == {"kind": "box", "n": 25, "box": None, "seed": 7}


def test_a_zoom_process_imports_the_pages_bifurc_not_a_checkout_in_its_working_folder(tmp_path):
    """A zoom process runs ``python -c`` from the page's working folder; a `bifurc` package there (another checkout)
    must not shadow the one the page runs."""
    import subprocess
    import bifurc
    from bifurc.explore.compute import child_argv
    (tmp_path / "bifurc").mkdir()
    (tmp_path / "bifurc" / "__init__.py").write_text("raise SystemExit('the checkout in the working folder')\n")
    out = subprocess.run(child_argv("import bifurc; print(bifurc.__file__)"), cwd=tmp_path, capture_output=True,
                         text=True, env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert out.returncode == 0, out.stderr
    assert Path(out.stdout.strip()).resolve() == Path(bifurc.__file__).resolve()
