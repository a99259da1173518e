"""rcl in a browser tab: the page's figures, side by side with native rcl.

    python3 bench/web.py [--site DIR]      (builds the site when no DIR)

Needs node/npm (to build), chromium, chromedriver and selenium. Prints:

(1) time from opening the page to the first ` ok`: a fresh profile
    (cold: nothing cached) and the same profile again (cached by the
    browser and the service worker);
(2) MAILBOT (Listing 6) from 8:00 to the end of the 4:30 trip, as fast as
    possible, in the page and in native CPython in this same run (as
    bench/mailbot.py runs it), and their ratio;
(3) drawings per second of the live view while both wheels drive, in
    real time (a 3.4-foot move at 2 MPH and a 25.5 IPS square), and
    where the time goes: the worker's frames (Python, conversion,
    postMessage), Fig. 1 worked out, the page's drawing of each;
(4) the size of the built site, as served and as gzip would send it;
(5) Stop during a real-time mile, Ctrl-C typed in the console and the
    Stop button in turn (--stops N of them): milliseconds of the page's
    clock from the key to the page's report of the motors off (a frame
    with every motor relay open), to " Interrupted" shown (the word
    stopped) and to the prompt back (window.rcl.stops); median and worst,
    and the load average meanwhile.

    --quick     leaves MAILBOT's day out (it takes minutes in the page)
    --stop-only only (5)
    --node      adds MAILBOT's day on the bare machine in Pyodide under Node
"""
import argparse
import gzip
import os
import pathlib
import shutil
import statistics
import sys
import tempfile
import threading
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
import rcl  # noqa: E402
from rcl.web.build import build  # noqa: E402
from rcl.web.cli import make_server  # noqa: E402

FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--window-size=1400,900")


def browser(profile):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    o = webdriver.ChromeOptions()
    for a in FLAGS + ("--user-data-dir=" + profile,):
        o.add_argument(a)
    o.binary_location = shutil.which("chromium") or shutil.which("chromium-browser")
    d = webdriver.Chrome(options=o, service=Service(shutil.which("chromedriver")))
    d.set_script_timeout(1800)
    return d


def call(d, script, *args):
    """A page Promise's value, polled (one long script call would outlast
    the driver's own timeout)."""
    d.execute_script("window.__result = null; Promise.resolve(%s).then("
                     "(v) => { window.__result = {v: v}; });" % script, *args)
    while True:
        r = d.execute_script("return window.__result")
        if r:
            return r["v"]
        time.sleep(0.05)


def until_ok(d, url):
    """Seconds from navigation start to the first ` ok` (the page's own clock)."""
    d.get(url)
    while not d.execute_script("return !!window.rcl"):
        time.sleep(0.05)
    return call(d, "window.rcl.ready.then(() => window.rcl.readyAt / 1000)")


def evaluate(d, text):
    return call(d, "(() => { const t = performance.now(); return window.rcl.evaluate(arguments[0])"
                   ".then((out) => [out, (performance.now() - t) / 1000]); })()", text)


def native_mailbot():
    m = rcl.open()
    m.include(os.path.join(rcl.SCREENS, "examples", "listing6.fs"))
    m.evaluate("8 AM TICKS!")
    t0 = time.perf_counter()
    m.evaluate("MAILBOT")
    return time.perf_counter() - t0, m.evaluate(".TIME").strip()


def set_rate(d, value):
    d.execute_script("const r = document.getElementById('rate'); r.value = arguments[0];"
                     "r.dispatchEvent(new Event('change'));", value)


NODE_SCRIPT = r"""
import { loadPyodide } from "%(site)s/pyodide/pyodide.mjs";
import fs from "node:fs";
const info = JSON.parse(fs.readFileSync("%(site)s/site.json"));
const py = await loadPyodide({ indexURL: "%(site)s/pyodide/" });
const purelib = py.runPython("import sysconfig; sysconfig.get_paths()['purelib']");
py.unpackArchive(new Uint8Array(fs.readFileSync("%(site)s/" + info.wheel)), "wheel", { extractDir: purelib });
py.runPython(`
import time, rcl
m = rcl.open()
m.evaluate("INCLUDE examples/listing6.fs")
m.evaluate("8 AM TICKS!")
t = time.monotonic()
m.evaluate("MAILBOT")
print("node", time.monotonic() - t, m.evaluate(".TIME").strip())
`);
"""


def node_mailbot(site):
    """MAILBOT's day on the bare machine (rcl.open()) in the same Pyodide
    under Node: no page, no session. -> seconds."""
    import subprocess
    script = os.path.join(tempfile.mkdtemp(prefix="rcl-web-node-"), "mailbot.mjs")
    with open(script, "w") as f:
        f.write(NODE_SCRIPT % {"site": os.path.abspath(site)})
    done = subprocess.run(["node", script], capture_output=True, text=True)
    line = [ln for ln in done.stdout.splitlines() if ln.startswith("node ")][-1]
    return float(line.split()[1])


def drawings_per_second(d):
    """-> drawings a second over the lines (real time), seconds, and the
    costs spent meanwhile (window.rcl.cost, differences)."""
    set_rate(d, "1")
    before = d.execute_script("return [window.rcl.view().frames, performance.now(), window.rcl.cost()]")
    evaluate(d, "RERB 2 MPH 3.4 FEET FORWARD\nINCLUDE examples/listing1.fs")
    after = d.execute_script("return [window.rcl.view().frames, performance.now(), window.rcl.cost()]")
    seconds = (after[1] - before[1]) / 1000
    return (after[0] - before[0]) / seconds, seconds, cost_between(before[2], after[2])


def cost_between(a, b):
    """Per-item costs between two window.rcl.cost() readings."""
    w0, w1, p0, p1 = a["worker"], b["worker"], a["page"], b["page"]
    frames, figures = w1["frames"] - w0["frames"], max(1, w1["figures"] - w0["figures"])
    draws = max(1, p1.get("draws", 0) - p0.get("draws", 0))
    return {
        "frames": frames,
        "frame_ms": 1000 * (w1["frame_s"] - w0["frame_s"]) / max(1, frames),
        "figure_ms": 1000 * (w1["figure_s"] - w0["figure_s"]) / figures,
        "figures": w1["figures"] - w0["figures"],
        "update_ms": (p1["update"] - p0["update"]) / max(1, frames),
        "top_ms": (p1["top"] - p0["top"]) / draws,
        "draw_figure_ms": (p1["figure"] - p0["figure"]) / max(1, p1["figures"] - p0["figures"]),
        "draws": draws,
    }


def print_cost(c, indent="    "):
    print("%sworker: %d frames, %.2f ms each (state, pen points, conversion, postMessage);"
          " Fig. 1 worked out %d times, %.1f ms each"
          % (indent, c["frames"], c["frame_ms"], c["figures"], c["figure_ms"]))
    print("%spage: a frame taken in %.2f ms; %d drawings of the top view, %.2f ms each;"
          " Fig. 1 drawn in %.2f ms" % (indent, c["update_ms"], c["draws"], c["top_ms"],
                                       c["draw_figure_ms"]))


def screenshot(d, url, path):
    """The page after Listing 1's square and a look at the pose: docs/img/web.png."""
    until_ok(d, url)
    from selenium.webdriver.common.by import By
    box = d.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea")
    for line in ("2 3 + .", "INCLUDE examples/listing1.fs", ".POSE", "HELP FORWARD"):
        box.send_keys(line + "\n")
        while d.execute_script("return window.rcl.busy()"):
            time.sleep(0.05)
    d.execute_script("document.getElementById('programs').value = 'examples/listing1.fs';"
                     "document.getElementById('programs').dispatchEvent(new Event('change'));")
    time.sleep(1)
    d.save_screenshot(path)


def stop_latency(d, tries=6):
    """Stops in the middle of a real-time `1 MILES FORWARD`, Ctrl-C typed in
    the console and the Stop button in turn: -> [(how, ms to the motors off
    shown, to " Interrupted" sent by the worker, shown, to the prompt)], in
    the page's clock from the key (window.rcl.stops)."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    set_rate(d, "1")
    box = d.find_element(By.CSS_SELECTOR, "#console .xterm-helper-textarea")
    out = []
    for i in range(tries):
        x = call(d, "window.rcl.pose()")["x"]
        box.send_keys("1 MILES FORWARD\n")
        while not d.execute_script("return window.rcl.busy() && window.rcl.view().pose.x > %f"
                                   % (x + 12)):
            time.sleep(0.05)
        n = len(d.execute_script("return window.rcl.stops"))
        if i % 2:
            how = "Stop button"
            d.find_element(By.ID, "stop").click()
        else:
            how = "Ctrl-C"
            box.send_keys(Keys.CONTROL, "c")
        while len(d.execute_script("return window.rcl.stops")) == n:
            time.sleep(0.05)
        s = d.execute_script("return window.rcl.stops")[-1]
        nan = float("nan")
        out.append((how, s.get("motors", nan), s.get("worker", nan), s.get("out", nan), s["prompt"],
                    s.get("sent", nan), s.get("motors_worker", nan), s.get("sigint", False)))
    return out


def print_stops(stops, load):
    print("(5) Stop in a real-time mile, ms from the key: the page passed it on / motors off"
          " sent by the worker / shown / ' Interrupted' sent / shown / the prompt back")
    for how, motors, worker, to_out, to_prompt, sent, motors_worker, sigint in stops:
        print("    %-12s %5.0f / %5.0f / %5.0f / %5.0f / %5.0f / %5.0f%s"
              % (how, sent, motors_worker, motors, worker, to_out, to_prompt,
                 "  (no tick took it: Python's SIGINT did)" if sigint else ""))
    for i, what in ((1, "motors off shown"), (3, "' Interrupted' shown")):
        values = [s[i] for s in stops]
        print("    %s: median %.0f ms, worst %.0f ms over %d stops"
              % (what, statistics.median(values), max(values), len(values)))
    print("    load average (1 min) before and after: %.1f, %.1f" % load, flush=True)


def site_size(folder):
    files = [p for p in pathlib.Path(folder).rglob("*") if p.is_file()]
    raw = sum(p.stat().st_size for p in files)
    packed = sum(len(gzip.compress(p.read_bytes(), 6)) for p in files)
    return raw, packed, len(files)


def main():
    p = argparse.ArgumentParser(description="rcl in a browser tab: the page's figures")
    p.add_argument("--site", help="a site rcl-web build made (default: build one now)")
    p.add_argument("--screenshot", metavar="PNG", help="only take the page's picture into PNG")
    p.add_argument("--quick", action="store_true", help="leave MAILBOT's day out")
    p.add_argument("--stops", type=int, default=10, metavar="N", help="stops to time (default 10)")
    p.add_argument("--stop-only", action="store_true", help="only time the stops")
    p.add_argument("--node", action="store_true",
                   help="also run MAILBOT's day on the bare machine in Pyodide under Node")
    args = p.parse_args()
    work = tempfile.mkdtemp(prefix="rcl-web-bench-")
    site = args.site or os.path.join(work, "site")
    if not args.site:
        build(site)
    server = make_server(site, 0)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = "http://127.0.0.1:%d/?rate=0" % server.server_address[1]
    profile = os.path.join(work, "profile")
    d = browser(profile)
    if args.screenshot:
        try:
            screenshot(d, url.replace("rate=0", "rate=100"), args.screenshot)
        finally:
            d.quit()
            server.shutdown()
        return
    if args.stop_only:
        try:
            until_ok(d, url)
            load = os.getloadavg()[0]
            stops = stop_latency(d, args.stops)
            print_stops(stops, (load, os.getloadavg()[0]))
        finally:
            d.quit()
            server.shutdown()
        return
    try:
        cold = until_ok(d, url)
        while not call(d, "window.rcl.cached()"):
            time.sleep(0.2)
        cold_phases = d.execute_script("return window.rcl.phases")
        cached = until_ok(d, url)
        print("(1) page opened to the first ` ok`: %.1f s cold, %.1f s cached" % (cold, cached))
        for name, ph in (("cold", cold_phases), ("cached", d.execute_script("return window.rcl.phases"))):
            print("    %s, the worker's start (s from its start): %s" % (
                name, ", ".join("%s %.1f" % (k, v / 1000) for k, v in ph.items())))
        sys.stdout.flush()
        fps, seconds, cost = drawings_per_second(d)
        print("(3) live view while both wheels drive, real time: %.0f drawings a second "
              "over %.1f s" % (fps, seconds))
        print_cost(cost)
        load = os.getloadavg()[0]
        stops = stop_latency(d, args.stops)
        print_stops(stops, (load, os.getloadavg()[0]))
        if not args.quick:
            set_rate(d, "0")
            evaluate(d, "INCLUDE examples/listing6.fs\n8 AM TICKS!")
            before = d.execute_script("return window.rcl.cost()")
            _, page_s = evaluate(d, "MAILBOT")
            cost = cost_between(before, d.execute_script("return window.rcl.cost()"))
            page_end = evaluate(d, ".TIME")[0].strip()
            native_s, native_end = native_mailbot()
            print("(2) MAILBOT 8:00 to %s: %.1f s in the page, %.1f s in native CPython: %.1fx "
                  "(the page ends at %s)" % (native_end, page_s, native_s, page_s / native_s, page_end))
            print_cost(cost)
            if args.node:
                node_s = node_mailbot(site)
                print("    the same day on the bare machine in Pyodide under Node: %.1f s (%.1fx native)"
                      % (node_s, node_s / native_s))
    finally:
        d.quit()
        server.shutdown()
    raw, packed, n = site_size(site)
    print("(4) the built site: %d files, %.1f MB (%.1f MB gzipped)" % (n, raw / 1e6, packed / 1e6))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
