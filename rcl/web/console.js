// The console: F83's screen in xterm.js. It only edits the line being
// typed (history with Up/Down, TAB completion asked of the machine) and
// shows what the machine prints; the ` ok`, the error texts and the
// `NAME]` prompt come from rcl's own shell (rcl/repl.py, via the worker).
import { Terminal } from "./xterm/xterm.mjs";

const HISTORY_KEY = "rcl.history";
const HISTORY_MAX = 500;

export class Console {
  // vm: {submit(line, shown) -> Promise(prompt), complete(text) -> Promise([names]),
  //      stop(at), answer(text)} (answer: a line or key for ACCEPT / KEY)
  constructor(element, vm) {
    this.vm = vm;
    this.term = new Terminal({ convertEol: true, cursorBlink: true, fontSize: 14,
      fontFamily: "ui-monospace, DejaVu Sans Mono, monospace", scrollback: 5000,
      theme: { background: "#111111" } });
    this.term.open(element);
    this.element = element;
    this.fit();
    window.addEventListener("resize", () => this.fit());
    this.tail = "";          // the text on the cursor's screen line
    this.line = "";          // what is being typed
    this.cursor = 0;
    this.busy = true;        // a line runs: keys wait (typed ahead)
    this.ahead = [];         // keys and lines typed while busy
    this.reading = null;     // a word waits for a line or a key
    this.history = JSON.parse(localStorage.getItem(HISTORY_KEY) || "[]");
    this.back = this.history.length;
    this.term.onData((data) => this.data(data));
    this.keyAt = null;       // when Ctrl-C was pressed (its event's time): a stop is timed from it
    element.addEventListener("keydown", (e) => {
      if (e.ctrlKey && (e.key === "c" || e.key === "C")) this.keyAt = e.timeStamp;
    }, true);
  }

  fit() {
    const cell = 8.5, rowH = 17;   // close enough for the monospace font at 14px
    const cols = Math.max(40, Math.floor((this.element.clientWidth - 8) / cell));
    const rows = Math.max(6, Math.floor((this.element.clientHeight - 8) / rowH));
    this.term.resize(cols, rows);
  }

  // -------------------------------------------------------------- output
  write(text) {
    this.term.write(text);
    const cut = Math.max(text.lastIndexOf("\n"), text.lastIndexOf("\r"));
    this.tail = cut >= 0 ? text.slice(cut + 1) : (this.tail + text).slice(-4096);
  }

  // The machine is ready for a line; `prompt` is the continuation prompt.
  ready(prompt) {
    this.prompt = prompt || "";
    this.write(this.prompt);
    this.line = ""; this.cursor = 0;
    this.busy = false;
    const queued = this.ahead; this.ahead = [];
    for (const d of queued) this.data(d);
  }

  redraw() {
    let s = "\r\x1b[K" + this.tail + this.line;
    const left = this.line.length - this.cursor;
    if (left > 0) s += "\x1b[" + left + "D";
    this.term.write(s);
  }

  // --------------------------------------------------------------- keys
  data(d) {
    if (d === "\x03") { this.interrupt(); return; }
    if (this.reading && this.reading.kind === "key") {
      this.reading = null; this.vm.answer(d[0] === "\r" ? "\r" : d); return;
    }
    if (this.busy && !this.reading) { this.ahead.push(d); return; }
    if (d.length > 1 && !d.startsWith("\x1b")) { this.paste(d); return; }
    switch (d) {
      case "\r": this.enter(); break;
      case "\x7f": case "\b":
        if (this.cursor > 0) {
          this.line = this.line.slice(0, this.cursor - 1) + this.line.slice(this.cursor);
          this.cursor--; this.redraw();
        }
        break;
      case "\x1b[3~":
        this.line = this.line.slice(0, this.cursor) + this.line.slice(this.cursor + 1);
        this.redraw(); break;
      case "\x1b[D": if (this.cursor > 0) { this.cursor--; this.redraw(); } break;
      case "\x1b[C": if (this.cursor < this.line.length) { this.cursor++; this.redraw(); } break;
      case "\x1b[H": case "\x01": this.cursor = 0; this.redraw(); break;
      case "\x1b[F": case "\x05": this.cursor = this.line.length; this.redraw(); break;
      case "\x15": this.line = ""; this.cursor = 0; this.redraw(); break;
      case "\x1b[A": this.recall(-1); break;
      case "\x1b[B": this.recall(1); break;
      case "\t": this.complete(); break;
      default:
        if (d >= " " && !d.startsWith("\x1b")) {
          this.line = this.line.slice(0, this.cursor) + d + this.line.slice(this.cursor);
          this.cursor += d.length; this.redraw();
        }
    }
  }

  paste(text) {
    const lines = text.replace(/\r\n?/g, "\n").split("\n");
    const last = lines.pop();
    if (lines.length === 0) { this.data(last); return; }
    lines[0] = this.line.slice(0, this.cursor) + lines[0];
    this.line = lines.shift(); this.cursor = this.line.length;
    this.ahead.push(...lines.map((l) => l + "\r"));
    if (last) this.ahead.push(last);
    this.enter();
  }

  enter() {
    const line = this.line, shown = this.tail;
    this.cursor = line.length; this.redraw();
    if (line.trim() && this.history[this.history.length - 1] !== line) {
      this.history.push(line);
      this.history = this.history.slice(-HISTORY_MAX);
      try { localStorage.setItem(HISTORY_KEY, JSON.stringify(this.history)); } catch (e) { /* full */ }
    }
    this.back = this.history.length;
    this.tail = shown + line;
    this.line = ""; this.cursor = 0;
    if (this.reading) {                       // ACCEPT: the line goes to the word
      this.reading = null;
      this.write("\n");
      this.vm.answer(line);
      return;
    }
    this.busy = true;
    this.vm.submit(line, shown).then((prompt) => this.ready(prompt));
  }

  // window.rcl.evaluate runs lines through the machine: the line being typed goes.
  beginExternal() {
    this.busy = true;
    if (this.line) { this.line = ""; this.cursor = 0; this.redraw(); }
  }

  // The page typed a line itself (Run, window.rcl.evaluate): as if typed.
  type(text) {
    for (const line of text.replace(/\r\n?/g, "\n").split("\n")) this.ahead.push(line + "\r");
    if (!this.busy) this.ready("");
  }

  recall(step) {
    const i = this.back + step;
    if (i < 0 || i > this.history.length) return;
    this.back = i;
    this.line = i === this.history.length ? "" : this.history[i];
    this.cursor = this.line.length; this.redraw();
  }

  async complete() {
    const before = this.line.slice(0, this.cursor);
    const word = before.split(/\s/).pop();
    if (!word) return;
    const names = await this.vm.complete(word);
    if (!names.length) return;
    let common = names[0];
    for (const n of names) {
      while (!n.toUpperCase().startsWith(common.toUpperCase())) common = common.slice(0, -1);
    }
    if (names.length > 1 && common.length <= word.length) {
      const saved = this.tail;
      this.term.write("\r\n" + names.slice(0, 60).join("  ") + (names.length > 60 ? "  …" : "") + "\r\n");
      this.tail = saved;
      this.redraw();
      return;
    }
    const put = names.length === 1 ? names[0] + " " : common;
    this.line = before.slice(0, before.length - word.length) + put + this.line.slice(this.cursor);
    this.cursor = before.length - word.length + put.length;
    this.redraw();
  }

  // Ctrl-C: a running word stops (motors first); at the prompt the line is dropped.
  interrupt() {
    this.ahead = [];
    const at = this.keyAt !== null && performance.now() - this.keyAt < 1000 ? this.keyAt : undefined;
    this.keyAt = null;
    if (this.busy || this.reading) { this.reading = null; this.vm.stop(at); return; }
    this.write("\n");
    this.ready(this.prompt);
  }

  // A word asks for a line (ACCEPT) or a key (KEY).
  read(kind) {
    this.reading = { kind };
    this.line = ""; this.cursor = 0;
    const queued = this.ahead; this.ahead = [];
    for (const d of queued) this.data(d);
  }
}
