// The VM's Web Worker: Pyodide, the rcl wheel, and rcl.web.session.Session.
// The page never waits on it: lines go in as messages, output and frames
// come out as messages while the word runs.
//
// Shared memory (when the page is cross-origin isolated):
//   ctl  Int32Array(4): [0] Pyodide's interrupt buffer (2 = Ctrl-C: Python's
//        SIGINT), set by the page only for a stop the ticks did not take;
//        [1] the rate the page asks for, x1000 (-1: flat out);
//        [2] a typed line or key is ready in io (ACCEPT, KEY);
//        [3] the page's stop flag (1: Stop or Ctrl-C), taken (back to 0) by
//        the session at a tick's end and what the pacer's sleep waits on,
//        so a stop wakes it at once: motors off there, then the break
//   io   Uint8Array: [0..3] length, then the line's UTF-8 bytes
import { loadPyodide } from "./pyodide/pyodide.mjs";

let py = null, Session = null, session = null, version = null, ctl = null, io = null;
// `at`: when it was sent, on the clock the page shares (a stop's report is timed by it)
const post = (type, data) => self.postMessage({ type, data, at: performance.timeOrigin + performance.now() });

function sleep(seconds) {
  const ms = Math.max(0, seconds * 1000);
  if (ctl) { Atomics.wait(ctl, 3, 0, ms); return; }
  const end = performance.now() + ms;          // not isolated: no other way
  while (performance.now() < end) { /* wait */ }
}

// The page's stop, taken once: by the session (a tick's end) or by the page's
// own fallback to Python's SIGINT, never both.
const stopAsked = () => ctl !== null && Atomics.compareExchange(ctl, 3, 1, 0) === 1;

function rateAsked() {
  if (!ctl) return null;
  const r = Atomics.load(ctl, 1);
  return r < 0 ? 0 : r / 1000;
}

// A word reads the keyboard (ACCEPT, KEY, DBG's keys): ask the page, wait for
// its answer; a stop meanwhile answers Ctrl-C ("\x03"), which the session
// raises as the terminal's read does (KeyboardInterrupt: the word aborts).
function waitInput(kind, shown) {
  if (!ctl) return null;                        // no shared memory: no input
  Atomics.store(ctl, 2, 0);
  post("read", { kind, shown });
  while (Atomics.load(ctl, 2) === 0) {
    if (stopAsked()) return "\x03";
    if (Atomics.compareExchange(ctl, 0, 2, 0) === 2) return "\x03";   // the page's fallback came first
    Atomics.wait(ctl, 2, 0, 50);
  }
  const n = new DataView(io.buffer).getInt32(0, true);
  return new TextDecoder().decode(io.slice(4, 4 + n));
}
const readLine = (shown) => waitInput("line", shown);
function readKey() {
  const k = waitInput("key", "");
  return k === null ? null : k === "" ? 13 : k.codePointAt(0);
}

function send(kind, data) {
  if (kind === "frame") {
    post("frame", data);                        // JSON text (frames_as_json): the page parses it
    const r = rateAsked();
    if (session && r !== null && r !== session.rate) session.set_rate(r);
  } else if (kind === "files") {
    post("files", data.toJs());
    data.destroy();
  } else {
    post(kind, data);
  }
}

async function start(msg) {
  const t0 = performance.now();
  ctl = msg.ctl ? new Int32Array(msg.ctl) : null;
  io = msg.io ? new Uint8Array(msg.io) : null;
  const phases = {};
  const phase = (name) => { phases[name] = Math.round(performance.now() - t0); };
  const site = await (await fetch("./site.json")).json();
  py = await loadPyodide({ indexURL: new URL("./pyodide/", location.href).href });
  phase("pyodide");
  const purelib = py.runPython("import sysconfig; sysconfig.get_paths()['purelib']");
  const wheel = await (await fetch("./" + site.wheel)).arrayBuffer();
  py.unpackArchive(new Uint8Array(wheel), "wheel", { extractDir: purelib });
  phase("wheel");
  if (ctl) py.setInterruptBuffer(ctl);
  py.FS.mkdirTree("/home/rcl");
  py.FS.chdir("/home/rcl");
  for (const [name, text] of Object.entries(msg.files || {})) py.FS.writeFile(name, text);
  let image = null;
  if (msg.image) {
    py.FS.writeFile("/tmp/start.img", new Uint8Array(msg.image));
    image = "/tmp/start.img";
  }
  Session = py.pyimport("rcl.web.session").Session;
  phase("import");
  session = openSession(image, msg.rate);
  phase("rcl");
  version = site.version;
  begin(t0, phases);
}

function openSession(image, rate) {
  const kw = { sleep, read_line: readLine, read_key: readKey, rate, frames_as_json: true,
               stop_asked: stopAsked };
  if (image) kw.image = image;
  return Session.callKwargs(send, kw);
}

function begin(t0, phases) {
  const prompt = session.banner();
  post("ready", { prompt, ms: performance.now() - t0, version, isolated: !!ctl, phases });
  session.frame();
}

// Open image…: a new machine from the image in this same Python (no reload);
// an image that cannot be opened leaves the machine as it was.
function reopen(msg) {
  const t0 = performance.now();
  py.FS.writeFile("/tmp/start.img", new Uint8Array(msg.image));
  let fresh;
  try {
    fresh = openSession("/tmp/start.img", msg.rate);
  } catch (e) {
    const lines = String(e.message).trim().split("\n");
    post("out", "\n" + msg.name + ": " + lines[lines.length - 1] + "\n");
    post("ready", { prompt: session.prompt, ms: 0, version, isolated: !!ctl, phases: {}, kept: true });
    return;
  }
  session.destroy();
  session = fresh;
  begin(t0, { rcl: Math.round(performance.now() - t0) });
}

function guarded(fn) {
  try { return fn(); } catch (e) { post("out", "\n(page) " + e.message + "\n"); return null; }
}

const handlers = {
  start: (msg) => start(msg).catch((e) => post("failed", String(e && e.message || e))),
  line: (msg) => {
    post("prompt", guarded(() => session.submit(msg.text, msg.shown || "")) || "");
    guarded(() => session.settle());
  },
  evaluate: (msg) => {
    post("result", { id: msg.id, value: guarded(() => session.evaluate(msg.text)) });
    guarded(() => session.settle());
  },
  complete: (msg) => {
    const names = guarded(() => session.complete(msg.text));
    post("result", { id: msg.id, value: names ? names.toJs() : [] });
  },
  pose: (msg) => {
    const s = session.state().toJs({ dict_converter: Object.fromEntries });
    post("result", { id: msg.id, value: s });
  },
  programs: (msg) => {
    const list = guarded(() => session.programs());
    post("result", { id: msg.id, value: list ? list.toJs() : [] });
  },
  "prompt-text": (msg) => post("result", { id: msg.id, value: session.prompt }),
  idle: () => guarded(() => session.catch_up()),
  image: reopen,
  rate: (msg) => guarded(() => session.set_rate(msg.rate)),
  write: (msg) => py.FS.writeFile(msg.name, msg.text),
  remove: (msg) => { try { py.FS.unlink(msg.name); } catch (e) { /* gone already */ } },
  fetch: (msg) => {
    let data = null;
    try { data = py.FS.readFile(msg.name); } catch (e) { /* none */ }
    post("result", { id: msg.id, value: data });
  },
};

self.onmessage = (e) => {
  if (ctl) { Atomics.store(ctl, 0, 0); Atomics.store(ctl, 3, 0); }   // a stop that came after its word
  const h = handlers[e.data.type];
  if (h) h(e.data);
};
