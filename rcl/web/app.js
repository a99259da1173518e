// The page: the console, the robot's view, the editor, and window.rcl.
// The VM runs in worker.js; this thread only draws and forwards keys.
import { Console } from "./console.js";
import { View } from "./view.js";
import { Files, cleanName, decodeProgram, encodeProgram, fragmentOptions } from "./programs.js";

const $ = (id) => document.getElementById(id);
const options = { ...Object.fromEntries(new URLSearchParams(location.search)), ...fragmentOptions() };
const embed = "embed" in options;
if (embed) document.body.classList.add("embed");

// ------------------------------------------------------- shared memory
// Stop and Ctrl-C reach the worker's Python through shared memory (a stop
// flag, and Pyodide's interrupt buffer as the fallback), which a browser
// gives only to a cross-origin isolated page.
const isolated = self.crossOriginIsolated && typeof SharedArrayBuffer !== "undefined";
const ctl = isolated ? new Int32Array(new SharedArrayBuffer(16)) : null;   // worker.js says what each is
const SIGINT_AFTER_MS = 50;   // a stop no tick took by then reaches Python as its SIGINT (a worker
                              // waiting for a core still takes it at its next tick: the faster path)
const DRIVEN = 0x3f, AUX_MOTORS = 0x05;   // the motor latch's relay and drive bits; ARM_ON, GRIP_ON
const io = isolated ? new Uint8Array(new SharedArrayBuffer(1 << 16)) : null;

function notice(text, ms = 4000) {
  const n = $("notice");
  n.textContent = text; n.hidden = false;
  clearTimeout(notice.timer);
  notice.timer = setTimeout(() => { n.hidden = true; }, ms);
}

// ------------------------------------------------------------- the VM
class VM {
  constructor() {
    this.pending = new Map(); this.next = 1;
    this.prompts = [];
    this.readyPromise = new Promise((resolve, reject) => { this.resolveReady = resolve; this.rejectReady = reject; });
    this.frame = null;
  }

  start(startOptions) {
    this.worker = new Worker("./worker.js", { type: "module" });
    this.worker.onmessage = (e) => this.message(e.data);
    this.worker.onerror = (e) => { $("state").textContent = "failed: " + e.message; };
    this.worker.postMessage({ type: "start", ctl: ctl && ctl.buffer, io: io && io.buffer,
                              rate: rate(), ...startOptions });
  }

  message({ type, data, at }) {
    if (type === "out") {
      if (data.includes("Interrupted")) this.stopped("worker", at - performance.timeOrigin);
      term.write(data);
      if (data.includes("Interrupted")) this.stopped("out");
    }
    else if (type === "frame") {
      data = JSON.parse(data);
      if (this.stopping && !(data.motor & DRIVEN) && !(data.aux & AUX_MOTORS)) {
        this.stopped("motors_worker", at - performance.timeOrigin);
        this.stopped("motors");
      }
      this.frame = data; view.update(data); status(data);
      if (window.rcl.onframe) window.rcl.onframe(data);
    }
    else if (type === "prompt") { const r = this.prompts.shift(); if (r) r(data); }
    else if (type === "result") { const r = this.pending.get(data.id); this.pending.delete(data.id); if (r) r(data.value); }
    else if (type === "read") term.read(data.kind);
    else if (type === "files") offerFiles(data);
    else if (type === "ready") ready(data);
    else if (type === "failed") { $("state").textContent = "failed: " + data; this.rejectReady(new Error(data)); }
  }

  ask(type, extra) {
    const id = this.next++;
    return new Promise((resolve) => {
      this.pending.set(id, resolve);
      this.worker.postMessage({ type, id, ...extra });
    });
  }

  post(type, extra) { this.worker.postMessage({ type, ...extra }); }

  // the console's side
  submit(line, shown) {
    running(true);
    return new Promise((resolve) => {
      this.prompts.push((p) => { running(false); resolve(p); });
      this.post("line", { text: line, shown });
    });
  }
  complete(text) { return this.ask("complete", { text }); }
  answer(text) {
    if (!io) return;
    const bytes = new TextEncoder().encode(text).slice(0, io.length - 4);
    new DataView(io.buffer).setInt32(0, bytes.length, true);
    io.set(bytes, 4);
    Atomics.store(ctl, 2, 1); Atomics.notify(ctl, 2);
  }
  // A stop's report, in the page's time from the key (window.rcl.stops):
  // `motors` when a frame showed every motor relay open (`motors_worker`:
  // when the worker sent it), `worker` when the worker printed
  // " Interrupted" (the word stopped), `out` when the page showed it,
  // `prompt` when the machine is ready for the next line; `motor` and
  // `aux`, the latches the last frame before the key showed; `sent` when
  // the page's handler passed the stop to the worker; `sigint` when no tick
  // took it within SIGINT_AFTER_MS (Python's SIGINT did).
  stopped(what, when = performance.now()) {
    const s = this.stopping;
    if (!s || s[what] !== undefined) return;
    s[what] = when - s.at;
    if (what === "prompt") { this.stopping = null; view.held = false; delete s.at; stops.push(s); }
  }

  // at: the key's or the click's time (its event's timeStamp), else now
  stop(at) {
    if (!busy) return;
    const f = this.frame || {};
    const now = performance.now();
    view.held = true;                 // no drawing until the stop is answered: its messages first
    this.stopping = { at: at === undefined ? now : at, motor: f.motor, aux: f.aux };
    this.stopping.sent = now - this.stopping.at;
    if (ctl) {
      Atomics.store(ctl, 3, 1); Atomics.notify(ctl, 3); Atomics.notify(ctl, 2);
      const stopping = this.stopping;
      setTimeout(() => {
        if (Atomics.compareExchange(ctl, 3, 1, 0) === 1 && busy) { Atomics.store(ctl, 0, 2); stopping.sigint = true; }
      }, SIGINT_AFTER_MS);
      return;
    }
    // not isolated: no way into a running worker but to end it
    notice("This page is not cross-origin isolated: Stop restarts the machine (your definitions are lost).", 8000);
    this.worker.terminate();
    for (const r of this.prompts.splice(0)) r("");
    for (const r of this.pending.values()) r(null);
    this.pending.clear();
    restart();
  }
}

let busy = false;
const stops = [];                    // the stops' reports, newest last (the bench reads them)
function running(on) {
  if (busy && !on) vm.stopped("prompt");
  busy = on;
  $("stop").disabled = !on;
  $("state").textContent = on ? "running" : "ready";
}

function rate() { return Number($("rate").value); }

function status(frame) {
  const text = frame.status + "   " + (frame.rate ? frame.rate + "x" : "flat out");
  if ($("status").textContent !== text) $("status").textContent = text;
}

// ------------------------------------------------------------- the page
const view = new View($("view"), $("figure"));
const vm = new VM();
const term = embed ? headless() : new Console($("console"), vm);
const files = new Files();
let userFiles = {};

function headless() {
  // embed mode: no console shown; lines still run through the same shell
  return {
    write() {}, prompt: "",
    read(kind) { vm.answer(kind === "key" ? "\r" : ""); },   // no keyboard here: an empty line
    ready(p) { this.prompt = p; },
    type(text) { for (const line of text.split("\n")) vm.submit(line, this.prompt).then((p) => this.ready(p)); },
  };
}

function ready(data) {
  $("state").textContent = "ready" + (data.isolated ? "" : " (not isolated: Stop restarts)");
  term.ready(data.prompt);
  running(false);
  window.rcl.startup = data.ms;
  window.rcl.phases = data.phases;          // the worker's start, ms: pyodide, wheel, import, rcl
  window.rcl.readyAt = performance.now();
  vm.resolveReady(true);
  if (ready.done) return;                   // a restart, an image opened: the page has these
  ready.done = true;
  vm.ask("programs", {}).then(fillPrograms);
  sharedProgram();
}

// ----------------------------------------------------------- programs
function fillPrograms(list) {
  const sel = $("programs");
  window.rcl.programs = Object.fromEntries(list || []);
  for (const [name] of list || []) {
    const o = document.createElement("option");
    o.value = name; o.textContent = name;
    sel.appendChild(o);
  }
}

function fillFiles(select) {
  const sel = $("files");
  sel.innerHTML = "";
  for (const name of Object.keys(userFiles).sort()) {
    const o = document.createElement("option");
    o.value = name; o.textContent = name; sel.appendChild(o);
  }
  if (select) sel.value = select;
}

function edit(name, text) {
  userFiles[name] = userFiles[name] === undefined ? text : userFiles[name];
  fillFiles(name);
  $("source").value = text;
}

async function saveFile() {
  const name = $("files").value || cleanName(prompt("File name", "program.fs") || "");
  if (!name) return null;
  userFiles[name] = $("source").value;
  await files.put(name, userFiles[name]);
  vm.post("write", { name, text: userFiles[name] });
  fillFiles(name);
  return name;
}

function download(name, data) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([data]));
  a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

async function offerFiles(names) {
  for (const name of names) {
    if (name.endsWith(".fs") && userFiles[name] !== undefined) continue;
    const data = await vm.ask("fetch", { name });
    if (data) { download(name, data); notice("Saved " + name + " (downloaded). Open image… starts from it."); }
  }
}

// A link carrying a program (#p=...&name=...): shown, run on a click.
async function sharedProgram() {
  if (!options.p) return;
  let text;
  try { text = await decodeProgram(options.p); } catch (e) { notice("This link's program cannot be read."); return; }
  const name = cleanName(options.name || "shared.fs");
  userFiles[name] = text;
  fillFiles(name);
  $("source").value = text;
  vm.post("write", { name, text });
  const run = $("run");
  run.hidden = false;
  run.onclick = () => { run.hidden = true; term.type("INCLUDE " + name); if (embed) run.hidden = false; };
}

async function share() {
  const name = $("files").value || "program.fs";
  const code = await encodeProgram($("source").value);
  const url = location.origin + location.pathname + "#p=" + code + "&name=" + encodeURIComponent(name);
  window.rcl.sharedLink = url;
  try { await navigator.clipboard.writeText(url); notice("Link copied: it carries the program (" + url.length + " characters)."); }
  catch (e) { window.prompt("The program's link:", url); }
}

// ---------------------------------------------------------- start, restart
let startImage = null;
function restart() {
  view.clear();
  vm.readyPromise = new Promise((resolve, reject) => { vm.resolveReady = resolve; vm.rejectReady = reject; });
  vm.start({ files: userFiles, image: startImage });
}

async function main() {
  try { userFiles = await files.all(); } catch (e) { userFiles = {}; }
  fillFiles(Object.keys(userFiles)[0]);
  if ($("files").value) $("source").value = userFiles[$("files").value];
  vm.start({ files: userFiles });
  if ("serviceWorker" in navigator && !("nosw" in options)) {
    navigator.serviceWorker.register("./sw.js").then(() => {
      // a host without the isolation headers: the worker adds them, once it controls the page
      if (!self.crossOriginIsolated && navigator.serviceWorker.controller === null) {
        navigator.serviceWorker.ready.then(() => {
          if (!sessionStorage.getItem("rcl.reloaded")) { sessionStorage.setItem("rcl.reloaded", "1"); location.reload(); }
        });
      }
    }).catch(() => {});
  }
  setInterval(() => { if (!busy && rate() > 0 && vm.frame) vm.post("idle"); }, 500);
}

// ---------------------------------------------------------- the controls
$("rate").onchange = () => {
  if (ctl) Atomics.store(ctl, 1, rate() > 0 ? rate() * 1000 : -1);
  vm.post("rate", { rate: rate() });
};
if (options.rate !== undefined && [...$("rate").options].some((o) => o.value === options.rate)) {
  $("rate").value = options.rate;
}
if (ctl) Atomics.store(ctl, 1, rate() > 0 ? rate() * 1000 : -1);
$("stop").onclick = (e) => vm.stop(e.timeStamp);
$("share").onclick = share;
$("programs").onchange = () => {
  const name = $("programs").value;
  if (!name) return;
  edit(name.split("/").pop(), window.rcl.programs[name]);
  $("programs").value = "";
};
$("new-file").onclick = () => {
  const name = cleanName(prompt("File name", "program.fs") || "");
  if (name) edit(name, "");
};
$("files").onchange = () => { $("source").value = userFiles[$("files").value] || ""; };
$("save-file").onclick = saveFile;
$("source").addEventListener("keydown", (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key === "s") { e.preventDefault(); saveFile(); }
});
$("include-file").onclick = async () => { const n = await saveFile(); if (n) term.type("INCLUDE " + n); };
$("download").onclick = () => download($("files").value || "program.fs", $("source").value);
$("delete-file").onclick = async () => {
  const name = $("files").value;
  if (!name || !confirm("Delete " + name + "?")) return;
  delete userFiles[name]; await files.remove(name); vm.post("remove", { name });
  fillFiles(); $("source").value = userFiles[$("files").value] || "";
};
$("upload").onclick = () => $("upload-file").click();
$("upload-file").onchange = async () => {
  for (const f of $("upload-file").files) {
    const name = cleanName(f.name), text = await f.text();
    userFiles[name] = text; await files.put(name, text); vm.post("write", { name, text });
    fillFiles(name); $("source").value = text;
  }
};
$("open-image").onclick = () => $("image-file").click();
$("image-file").onchange = async () => {
  const f = $("image-file").files[0];
  if (!f) return;
  startImage = await f.arrayBuffer();
  term.write("\n(starting from " + f.name + ")\n");
  if (busy) { vm.worker.terminate(); restart(); return; }
  // the worker opens it in the Python it has: no reload
  view.clear();
  vm.readyPromise = new Promise((resolve, reject) => { vm.resolveReady = resolve; vm.rejectReady = reject; });
  running(true);
  vm.post("image", { image: startImage.slice(0), name: f.name, rate: rate() });
};

// ------------------------------------------------------------ window.rcl
window.rcl = {
  get ready() { return vm.readyPromise; },
  // the text as if typed; -> what it printed (` ok` and error texts included)
  evaluate(text) {
    return vm.readyPromise.then(() => new Promise((resolve) => {
      const before = term.prompt;
      if (term.beginExternal) term.beginExternal();
      running(true);
      vm.ask("evaluate", { text }).then((value) => {
        running(false);
        vm.ask("prompt-text", {}).then((p) => { term.ready(p === null ? before : p); resolve(value); });
      });
    }));
  },
  // the robot now, as .POSE prints it: inches and degrees (the latest frame)
  pose() {
    const f = vm.frame || { x: 0, y: 0, heading: 0 };
    return Promise.resolve({ x: f.x, y: f.y, heading: f.heading });
  },
  time() { return vm.frame ? vm.frame.t : 0; },
  stop() { vm.stop(); },
  stops,
  view() { return view.state(); },
  // where the time goes: the worker's frames and Fig. 1 (seconds, counts), the page's drawing (ms)
  cost() { return { worker: vm.frame ? vm.frame.cost : null, page: view.state().cost }; },
  // the console's text, its last `rows` screen rows, a line the terminal
  // wrapped joined again
  screen(rows = 200) {
    if (!term.term) return "";
    const b = term.term.buffer.active, out = [];
    for (let i = Math.max(0, b.length - rows); i < b.length; i++) {
      const line = b.getLine(i), text = line.translateToString(true);
      if (line.isWrapped && out.length) out[out.length - 1] += text; else out.push(text);
    }
    return out.join("\n").replace(/\n+$/, "");
  },
  busy() { return busy; },
  cached() { return caches.keys().then((k) => k.some((n) => n.startsWith("rcl-site-") && n.endsWith("-complete"))); },
};

main();
