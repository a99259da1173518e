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
    real time (a 3.4-foot move at 2 MPH and a 25.5 IPS square);
(4) the size of the built site, as served and as gzip would send it;
(5) Stop during a real-time mile: milliseconds from the key to the
    prompt back (the word stopped, motors off).
"""
import argparse
import gzip
import os
import pathlib
import shutil
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


def drawings_per_second(d):
    d.execute_script("const r = document.getElementById('rate'); r.value = '1';"
                     "r.dispatchEvent(new Event('change'));")
    f0, t0 = d.execute_script("return [window.rcl.view().frames, performance.now()]")
    evaluate(d, "RERB 2 MPH 3.4 FEET FORWARD\nINCLUDE examples/listing1.fs")
    f1, t1 = d.execute_script("return [window.rcl.view().frames, performance.now()]")
    return (f1 - f0) / ((t1 - t0) / 1000), (t1 - t0) / 1000


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


def stop_latency(d, tries=5):
    """Milliseconds from Stop (window.rcl.stop) to the prompt back, the
    motors off, in the middle of a real-time `1 MILES FORWARD`."""
    d.execute_script("const r = document.getElementById('rate'); r.value = '1';"
                     "r.dispatchEvent(new Event('change'));")
    out = []
    for _ in range(tries):
        d.execute_script("window.rcl.evaluate('1 MILES FORWARD')")
        while not call(d, "window.rcl.pose()")["x"] or not d.execute_script(
                "return window.rcl.busy() && window.rcl.view().pose.t > 0"):
            time.sleep(0.05)
        time.sleep(1.0)
        out.append(call(d, "new Promise((done) => { const t = performance.now(); window.rcl.stop();"
                           "(function poll() { window.rcl.busy() ? setTimeout(poll, 1)"
                           " : done(performance.now() - t); })(); })"))
    return out


def site_size(folder):
    files = [p for p in pathlib.Path(folder).rglob("*") if p.is_file()]
    raw = sum(p.stat().st_size for p in files)
    packed = sum(len(gzip.compress(p.read_bytes(), 6)) for p in files)
    return raw, packed, len(files)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--site", help="a site rcl-web build made (default: build one now)")
    p.add_argument("--screenshot", metavar="PNG", help="only take the page's picture into PNG")
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
    try:
        cold = until_ok(d, url)
        while not call(d, "window.rcl.cached()"):
            time.sleep(0.2)
        cached = until_ok(d, url)
        print("(1) page opened to the first ` ok`: %.1f s cold, %.1f s cached" % (cold, cached))
        evaluate(d, "INCLUDE examples/listing6.fs\n8 AM TICKS!")
        _, page_s = evaluate(d, "MAILBOT")
        page_end = evaluate(d, ".TIME")[0].strip()
        native_s, native_end = native_mailbot()
        print("(2) MAILBOT 8:00 to %s: %.1f s in the page, %.1f s in native CPython: %.1fx "
              "(the page ends at %s)" % (native_end, page_s, native_s, page_s / native_s, page_end))
        fps, seconds = drawings_per_second(d)
        print("(3) live view while both wheels drive, real time: %.0f drawings a second "
              "over %.1f s" % (fps, seconds))
        stops = stop_latency(d)
        print("(5) Stop in a real-time mile to the prompt back: %s ms (worst %.0f ms)"
              % (" ".join("%.0f" % s for s in stops), max(stops)))
    finally:
        d.quit()
        server.shutdown()
    raw, packed, n = site_size(site)
    print("(4) the built site: %d files, %.1f MB (%.1f MB gzipped)" % (n, raw / 1e6, packed / 1e6))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
