"""rcl in a browser tab (rcl/web): the site `rcl-web build` makes, run
under Node with the pinned Pyodide (no browser) and in Debian's headless
Chromium driven by selenium.

The site is built once per session (npm ci of rcl/web's lock) and served
once; one browser (`page`) runs every test it can, one fresh profile
(`fresh`) the shared link, the offline load and the embed mode. Without
node/npm or chromium/chromedriver the tests skip, naming what to install;
with RCL_REQUIRE_WEB=1 (CI) they fail instead. Virtual time is
deterministic: the counts in the page are exactly those of rcl.open()
here. Waits are bounded by what the page reports (ready, busy, the view's
pose), generously; nothing asserts on wall-clock speed.
"""
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time

import pytest

import rcl

REQUIRED = os.environ.get("RCL_REQUIRE_WEB") == "1"
NODE_LINE = "node and npm are needed: sudo apt-get install nodejs npm"
BROWSER_LINE = ("chromium, chromedriver and selenium are needed: "
                "sudo apt-get install chromium chromium-driver; pip install selenium")
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
PATIENCE = 600                 # seconds: a bound on waits, never an expectation
COMMAND = "RERB 2 MPH 3.4 FEET FORWARD"


def missing(why):
    if REQUIRED:
        pytest.fail("RCL_REQUIRE_WEB=1 but " + why)
    pytest.skip(why)


@pytest.fixture(scope="session")
def site(tmp_path_factory):
    """The built site: `rcl-web build DIR` (rcl.web.build.build)."""
    if not (shutil.which("node") and shutil.which("npm")):
        missing(NODE_LINE)
    from rcl.web.build import build
    folder = tmp_path_factory.mktemp("site")
    build(str(folder))
    return folder


def cpython(lines):
    """The same lines on rcl.open() here: (wheel counts, pose, output)."""
    m = rcl.open()
    out = [m.evaluate(line) for line in lines]
    return list(m.sim.wheel_counts), [round(v, 6) for v in m.sim.pose], out


# ------------------------------------------------------ Node, no browser
NODE_SCRIPT = r"""
import { loadPyodide } from "%(site)s/pyodide/pyodide.mjs";
import fs from "node:fs";
const site = "%(site)s";
const info = JSON.parse(fs.readFileSync(site + "/site.json"));
const py = await loadPyodide({ indexURL: site + "/pyodide/" });
const purelib = py.runPython("import sysconfig; sysconfig.get_paths()['purelib']");
py.unpackArchive(new Uint8Array(fs.readFileSync(site + "/" + info.wheel)), "wheel",
                 { extractDir: purelib });
py.runPython(fs.readFileSync(0, "utf8"));
"""

NODE_PYTHON = """
import json, sys, rcl
def run(lines):
    m = rcl.open()
    out = [m.evaluate(line) for line in lines]
    return [list(m.sim.wheel_counts), [round(v, 6) for v in m.sim.pose], out]
mods = [n for n in ("prompt_toolkit", "serial", "usb") if n in sys.modules]
print(json.dumps({"first": run(%(first)r), "listing1": run(%(listing)r), "modules": mods}))
"""

FIRST = [COMMAND, ".POSE"]
LISTING1 = ["INCLUDE examples/listing1.fs", ".POSE"]


def test_under_node_the_wheel_loads_and_gives_the_cpython_counts(site, tmp_path):
    script = tmp_path / "run.mjs"
    script.write_text(NODE_SCRIPT % {"site": site})
    done = subprocess.run(["node", str(script)], input=NODE_PYTHON % {"first": FIRST, "listing": LISTING1},
                          capture_output=True, text=True, timeout=PATIENCE)
    assert done.returncode == 0, done.stderr[-2000:]
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert got["first"] == list(cpython(FIRST))
    assert all(1159 <= c <= 1161 for c in got["first"][0])     # 3.4 ft: 1160 counts a wheel
    assert got["listing1"] == list(cpython(LISTING1))
    assert got["modules"] == []                     # none of rcl's terminal/link packages


# ------------------------------------------------------------ the browser
def serve(folder):
    from rcl.web.cli import make_server
    server = make_server(str(folder), 0)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, "http://127.0.0.1:%d/" % server.server_address[1]


@pytest.fixture(scope="session")
def browsers():
    """Start fresh headless Chromium profiles; all quit at the end."""
    if not (CHROMIUM and CHROMEDRIVER):
        missing(BROWSER_LINE)
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        missing(BROWSER_LINE)
    started, profiles = [], []

    def start():
        o = webdriver.ChromeOptions()
        profile = tempfile.mkdtemp(prefix="rcl-web-profile-")
        profiles.append(profile)
        for a in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update",
                  "--disable-sync", "--window-size=1400,900", "--user-data-dir=" + profile):
            o.add_argument(a)
        o.binary_location = CHROMIUM
        d = webdriver.Chrome(options=o, service=Service(CHROMEDRIVER))
        d.set_script_timeout(PATIENCE)
        started.append(d)
        return d
    yield start
    for d in started:
        try:
            d.quit()
        except Exception:
            pass
    for p in profiles:
        shutil.rmtree(p, ignore_errors=True)


@pytest.fixture(scope="session")
def server(site):
    srv, url = serve(site)
    yield url
    srv.shutdown()
    srv.server_close()


def open_page(d, url):
    d.get(url)
    wait_ready(d)


def wait_ready(d):
    assert call(d, "window.rcl.ready.then(() => 'ready')") == "ready"


def call(d, expression):
    """A window.rcl Promise's value (polled: one long script call would
    outlast the driver's own timeout)."""
    d.execute_script(
        "window.__result = null; Promise.resolve(%s).then("
        "(v) => { window.__result = {v: v}; }, (e) => { window.__result = {v: 'failed: ' + e}; });"
        % expression)
    return wait_for(d, "window.__result", "an answer to " + expression)["v"]


def wait_for(d, script, what, timeout=PATIENCE):
    """Poll a page expression until it is truthy (bounded, generously)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = d.execute_script("return window.rcl && (%s)" % script)
        if value:
            return value
        time.sleep(0.05)
    pytest.fail("the page never reported " + what)


def type_line(d, text):
    from selenium.webdriver.common.by import By
    box = d.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea")
    box.send_keys(text + "\n")


def set_rate(d, value):
    """The time menu: '1' real time, '10', '100', '0' as fast as possible."""
    d.execute_script("const r = document.getElementById('rate'); r.value = arguments[0];"
                     "r.dispatchEvent(new Event('change'));", value)


def wait_idle(d):
    wait_for(d, "window.rcl && !window.rcl.busy()", "the end of the word")


@pytest.fixture(scope="session")
def page(browsers, server):
    """The built site, served locally, open as fast as the machine goes."""
    d = browsers()
    open_page(d, server + "?rate=0")
    return d


def test_the_served_site_loads_to_the_ok_prompt(page):
    assert page.execute_script("return self.crossOriginIsolated") is True
    assert "F83-style Forth for the R-E Robot" in page.execute_script("return window.rcl.screen()")


def test_typed_command_and_pose_print_what_the_terminal_prints(page):
    type_line(page, COMMAND)
    wait_idle(page)
    type_line(page, ".POSE")
    wait_for(page, "window.rcl.screen().includes('.POSE x ')", "the pose")
    wait_idle(page)
    counts, pose, out = cpython(FIRST)
    screen = page.execute_script("return window.rcl.screen()").splitlines()
    assert COMMAND + "  ok" in screen
    assert ".POSE " + out[1] + " ok" in screen                  # x 40.76 in  y 0.00 in ...
    got = call(page, "window.rcl.pose()")
    assert [round(got[k], 6) for k in ("x", "y")] == pose[:2]


def test_the_drawn_robot_advances_during_a_real_time_move(page, tmp_path):
    """The view's state is sampled in the page at each animation frame (a
    slow poll from here, or the screenshot, cannot miss the move's two
    seconds); a screenshot is taken as soon as it was seen moving."""
    set_rate(page, "1")
    start = call(page, "window.rcl.pose()")["x"]
    page.execute_script(
        "window.__seen = []; const sample = () => { const v = window.rcl.view();"
        " if (window.rcl.busy() && %f < v.pose.x && v.pose.x < %f)"
        "   window.__seen.push([v.pose.x, v.robot.x, v.frames]);"
        " if (window.__seen !== null) requestAnimationFrame(sample); };"
        " requestAnimationFrame(sample);" % (start + 1, start + 39))
    type_line(page, COMMAND)
    shot = tmp_path / "moving.png"
    end = time.monotonic() + PATIENCE
    while time.monotonic() < end:
        busy, seen = page.execute_script("return [window.rcl.busy(), window.__seen.length]")
        if seen and not shot.exists():
            page.save_screenshot(str(shot))
        if not busy and page.execute_script("return window.rcl.view().pose.x") > start + 39:
            break
        time.sleep(0.02)
    seen = page.execute_script("const s = window.__seen; window.__seen = null; return s;")
    assert len(seen) >= 2, "the view never showed the robot between start and end"
    xs = [s[0] for s in seen]
    assert xs == sorted(xs) and xs[-1] > xs[0]                   # forward, drawn further right
    assert seen[-1][1] > seen[0][1] and seen[-1][2] > seen[0][2]
    assert shot.stat().st_size > 0
    wait_idle(page)


DRIVEN = 0x35                  # the motor latch: both relays closed, both drives on (rcl/robot.py)


@pytest.mark.parametrize("how", ["ctrl-c", "stop-button"])
def test_a_stop_in_a_mile_turns_the_motors_off_first_and_the_next_move_works(page, how):
    """Ctrl-C in the console, or the Stop button, in the middle of a real
    -time `1 MILES FORWARD`: the page's report (window.rcl.stops) says the
    wheels were driven when the key came, and a frame with every motor
    relay open (the board's latch, drawn) reached the page no later than
    the ` Interrupted` text; the robot coasts to rest and moves again."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    set_rate(page, "1")
    start = call(page, "window.rcl.pose()")["x"]
    type_line(page, "1 MILES FORWARD")
    wait_for(page, "window.rcl.view().pose.x > %f && window.rcl.view().relays.motor === %d"
             % (start + 6, DRIVEN), "the robot moving, wheels driven")
    stops = len(page.execute_script("return window.rcl.stops"))
    if how == "ctrl-c":
        page.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea").send_keys(Keys.CONTROL, "c")
    else:
        page.find_element(By.ID, "stop").click()
    wait_idle(page)
    lines = page.execute_script("return window.rcl.screen()").splitlines()
    assert any(line.startswith("1 MILES FORWARD ") and "Interrupted" in line for line in lines)
    report = page.execute_script("return window.rcl.stops")[stops:]
    assert len(report) == 1
    r = report[0]
    assert r["motor"] == DRIVEN                                  # driven when the key came
    assert 0 <= r["motors"] <= r["out"] <= r["prompt"]           # motors off shown first
    assert page.execute_script("return window.rcl.view().relays") == {"motor": 0, "aux": 0}
    set_rate(page, "0")
    assert call(page, "window.rcl.evaluate('2 SECONDS MOVING @ .')") == " 0  ok"   # it coasted to rest
    stopped = call(page, "window.rcl.pose()")["x"]
    assert stopped < start + 12 * 5280 / 10                     # far short of the mile
    assert call(page, "window.rcl.evaluate('%s')" % COMMAND) == "  ok"
    after = call(page, "window.rcl.pose()")["x"]
    assert after - stopped == pytest.approx(40.8, abs=0.5)      # the 3.4 feet, from where it stopped


# ------------------------------------------- time, input, files, images
def frames_during(d, text):
    """The frames the page received while `text` ran: [t, wall, behind,
    pacer] (up to its answer: not those of the idle catch-up after it)."""
    d.execute_script("window.__frames = []; window.rcl.onframe = (f) =>"
                     " window.__frames.push([f.t, f.wall, f.behind, f.pacer]);")
    out = call(d, "window.rcl.evaluate(%s).then((v) => { window.rcl.onframe = null; return v; })"
               % json.dumps(text))
    return out, d.execute_script("return window.__frames")


@pytest.mark.parametrize("rate,wait", [(10, 20), (100, 50)])
def test_at_10x_and_100x_the_virtual_clock_runs_at_that_rate(page, rate, wait):
    """Each frame says the virtual time, the worker's wall clock, how far
    the virtual clock is behind the rate (the machine cannot always keep
    up at 100x) and which pacer paced it: under one pacer, virtual time
    plus its lag grows `rate` times the wall."""
    set_rate(page, str(rate))
    out, frames = frames_during(page, "%d SECONDS" % wait)
    set_rate(page, "0")
    assert out == "  ok"
    paced = [f for f in frames if f[3] == frames[-1][3]]
    assert len(paced) >= 10, frames
    (t0, w0, b0, _), (t1, w1, b1, _) = paced[0], paced[-1]
    assert t1 - t0 >= 0.8 * wait
    lead = (t1 - t0) + (b1 - b0)                 # the virtual seconds the rate asked for
    assert lead == pytest.approx(rate * (w1 - w0), rel=0.1, abs=0.05 * rate)


def test_accept_and_key_read_what_is_typed_in_the_console(page):
    type_line(page, ": ASK  PAD 40 ACCEPT PAD SWAP TYPE ;")
    wait_idle(page)
    type_line(page, "ASK")
    type_line(page, "hello robot")              # typed ahead: ACCEPT takes it
    wait_for(page, "window.rcl.screen().includes('hello robot ok')", "ACCEPT's line")
    wait_idle(page)
    type_line(page, "KEY .")
    from selenium.webdriver.common.by import By
    page.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea").send_keys("A")
    wait_for(page, "window.rcl.screen().includes('KEY . 65  ok')", "KEY's code")
    wait_idle(page)


def screen_after(d, marker):
    """The console's lines from the last one starting with marker."""
    lines = d.execute_script("return window.rcl.screen(400)").splitlines()
    starts = [i for i, line in enumerate(lines) if line.startswith(marker)]
    return lines[starts[-1]:] if starts else []


def test_dbg_steps_a_word_with_single_keys_in_the_console(page):
    """DBG in the page as in the terminal: each key (no Enter after it)
    is a command; Enter steps, C continues; each step's line names the
    place, the word about to run and the stack; Stop while the view
    waits for a key interrupts as Ctrl-C at KEY does."""
    from selenium.webdriver.common.by import By
    set_rate(page, "0")
    box = page.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea")
    type_line(page, ": THREE  1 . 2 . 3 . ;")
    wait_idle(page)
    type_line(page, "DBG THREE")
    step = "  (typed)  THREE > .  ( %d )  "
    wait_for(page, "window.rcl.screen().includes(%s)" % json.dumps(step % 1), "the first step")
    box.send_keys("\n")                                # Enter: `.` runs, 1 printed
    wait_for(page, "window.rcl.screen().includes(%s)" % json.dumps(step % 2), "the second step")
    box.send_keys("\n")
    wait_for(page, "window.rcl.screen().includes(%s)" % json.dumps(step % 3), "the third step")
    box.send_keys("c")                                 # continue: the rest runs
    wait_idle(page)
    shown = screen_after(page, "DBG THREE   Enter step")
    assert shown[0] == "DBG THREE   Enter step  I into  O over  F finish  C continue  Q stop"
    assert [line[:len(step % 1)] for line in shown[1:6:2]] == [step % n for n in (1, 2, 3)]
    assert shown[2] == "1 " and shown[4] == "2 " and shown[6] == "3 "
    assert shown[7].startswith("  done  ( )  ") and shown[7].endswith(" ok")
    type_line(page, "DBG THREE")                       # Stop while the view waits for a key
    wait_for(page, "window.rcl.screen().split('\\n').slice(-1)[0].startsWith(%s)" % json.dumps(step % 1),
             "the view waiting")
    page.find_element(By.ID, "stop").click()
    wait_idle(page)
    shown = [line for line in screen_after(page, "DBG THREE   Enter step") if line.strip()]
    assert len(shown) == 2 and shown[1].startswith(step % 1) and shown[1].rstrip().endswith(" Interrupted")
    assert call(page, "window.rcl.evaluate('2 3 + .')") == " 5  ok"


def downloads(d, folder):
    d.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(folder)})


def downloaded(folder, name):
    path = folder / name
    end = time.monotonic() + PATIENCE
    while time.monotonic() < end:
        if path.exists() and not any(p.suffix == ".crdownload" for p in folder.iterdir()):
            return path.read_bytes()
        time.sleep(0.05)
    pytest.fail("%s was never downloaded" % name)


def choose_file(d, input_id, path):
    d.execute_script("document.getElementById(arguments[0]).hidden = false;", input_id)
    d.find_element("id", input_id).send_keys(str(path))
    d.execute_script("document.getElementById(arguments[0]).hidden = true;", input_id)


def test_an_uploaded_fs_file_is_included_and_downloads_as_it_was(page, tmp_path):
    text = "\\ uploaded\n: UPLOADED  ( -- n )  7 6 * ;\n"
    mine = tmp_path / "mine.fs"
    mine.write_text(text)
    choose_file(page, "upload-file", mine)
    wait_for(page, "document.getElementById('files').value === 'mine.fs'", "the file in the editor")
    assert page.execute_script("return document.getElementById('source').value") == text
    assert call(page, "window.rcl.evaluate('INCLUDE mine.fs UPLOADED .')") == " 42  ok"
    folder = tmp_path / "downloads"
    folder.mkdir()
    downloads(page, folder)
    page.find_element("id", "download").click()
    assert downloaded(folder, "mine.fs").decode() == text


def test_save_system_downloads_an_image_that_opens_with_the_definitions(page, tmp_path):
    folder = tmp_path / "downloads"
    folder.mkdir()
    downloads(page, folder)
    assert call(page, "window.rcl.evaluate(': TWICE  2 * ;')") == "  ok"
    assert call(page, "window.rcl.evaluate('SAVE-SYSTEM twice.img')").endswith(" ok")
    image = downloaded(folder, "twice.img")
    assert len(image) > 1000
    choose_file(page, "image-file", folder / "twice.img")
    wait_for(page, "window.rcl.screen().includes('(starting from twice.img)')", "the restart")
    wait_ready(page)
    assert call(page, "window.rcl.evaluate('21 TWICE .')") == " 42  ok"


# ------------------------------------- a fresh profile: a link, offline, embedded
@pytest.fixture(scope="session")
def fresh(site, browsers):
    """A fresh browser profile and a server of its own (stopped for the
    offline load)."""
    srv, url = serve(site)
    state = {"driver": browsers(), "url": url, "server": srv}
    yield state
    if state["server"] is not None:
        srv.shutdown()
        srv.server_close()


def test_a_shared_link_opened_in_a_fresh_profile_shows_and_runs_the_program(page, server, fresh):
    page.execute_script("document.getElementById('source').value = arguments[0];", SHARED)
    page.find_element("id", "share").click()
    link = wait_for(page, "window.rcl.sharedLink", "the link")
    assert link.startswith(server) and "#p=" in link and "FORWARD" not in link
    fresh["link"] = link[len(server):]
    d = fresh["driver"]
    open_page(d, fresh["url"] + fresh["link"])
    wait_for(d, "document.getElementById('source').value", "the program")
    assert d.execute_script("return document.getElementById('source').value") == SHARED
    run_shared(d)


SHARED = "RERB 3 MPH\n2 FEET FORWARD 90 DEGREES LEFT\n.POSE"


def run_shared(d):
    run = d.find_element("id", "run")
    assert run.is_displayed()
    start = call(d, "window.rcl.pose()")
    run.click()
    wait_for(d, "window.rcl.screen().includes('heading 90.0 deg') || "
                "window.rcl.view().pose.heading > 89", "the program's end")
    wait_idle(d)
    pose = call(d, "window.rcl.pose()")
    assert pose["x"] - start["x"] == pytest.approx(24, abs=1)
    assert pose["heading"] == pytest.approx(90, abs=1)


def test_offline_after_the_first_visit_in_embed_mode_only_the_robot_and_run(fresh):
    d = fresh["driver"]
    if "link" not in fresh:
        open_page(d, fresh["url"] + "?rate=0")
    wait_for(d, "window.__cached || (window.rcl.cached().then((c) => window.__cached = c), false)",
             "the site cached")
    srv, fresh["server"] = fresh["server"], None
    srv.shutdown()
    srv.server_close()
    d.get(fresh["url"] + "?embed&rate=0" + fresh.get("link", ""))
    wait_ready(d)
    assert call(d, "window.rcl.evaluate('2 3 + .')") == " 5  ok"      # offline, it runs
    shown = d.execute_script(
        "return ['bar', 'left', 'figure', 'view', 'status'].map((id) => {"
        " const r = document.getElementById(id).getBoundingClientRect(); return r.width > 0 && r.height > 0; })")
    assert shown == [False, False, False, True, True]
    if "link" in fresh:
        run_shared(d)
