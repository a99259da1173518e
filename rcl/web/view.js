// The robot, live: a top view (robot with heading, arm and jaws, its path
// as a pen, a grid in feet, the start) that follows and zooms, and Fig. 1
// of the article (wheel speeds with the commanded speed and breakpoints,
// following error against its limit). Everything drawn comes from the
// board's observation hook: the trace rows and the Fig. 1 series that
// rcl.web.session sends in frames (rcl.sim.observe.Trace, rcl.track).

const BODY_IN = 9;            // the drawn base's radius, inches
const TRACK_IN = 44 / Math.PI;
const PATH_MAX = 200000;      // points of the pen kept (memory stays bounded)
const STEP_IN = 0.05;         // the pen takes a point this far from the last
const STRAIGHT_IN = 0.01;     // a point this close to the line on goes into that line
const COLOURS = { left: "#1f77b4", right: "#ff7f0e" };
const LEFT_DRIVEN = 0x11, RIGHT_DRIVEN = 0x24;   // M1_ON | M1_GO, M2_ON | M2_GO (rcl/robot.py)

export class View {
  constructor(canvas, figureCanvas) {
    this.canvas = canvas;
    this.fig = figureCanvas;
    this.path = [];                     // [x, y] in inches, the pen (a polyline)
    this.pen = new Path2D();            // path[0 .. length-2] in inches, kept, extended
    this.penLength = 0;                 // the points pen holds (all but the last)
    this.direction = null;              // the last segment's first direction, a unit vector
    this.start = null;
    this.pose = { x: 0, y: 0, heading: 0, arm: 8, jaw: 0, t: 0 };
    this.relays = { motor: 0, aux: 0 };   // the board's latches: a driven wheel is drawn green
    this.figure = null;
    this.zoom = 1;                      // the user's, on top of the fit
    this.scale = 4;                     // pixels per inch, eased
    this.centre = { x: 0, y: 0 };
    this.frames = 0;                    // drawings made (frames per second)
    this.robotPx = { x: 0, y: 0 };
    this.dirty = true;
    this.figureDirty = true;            // Fig. 1 is drawn again only when it changed
    this.cost = { update: 0, draws: 0, top: 0, figures: 0, figure: 0 };   // ms spent, for the bench
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      this.zoom = Math.min(20, Math.max(0.05, this.zoom * (e.deltaY < 0 ? 1.2 : 1 / 1.2)));
      this.dirty = true;
    }, { passive: false });
    canvas.addEventListener("dblclick", () => { this.zoom = 1; this.dirty = true; });
    this.held = false;                  // a stop under way: the page's thread answers it first
    const loop = () => { if (this.dirty && !this.held) this.draw(); requestAnimationFrame(loop); };
    requestAnimationFrame(loop);
  }

  // A frame from the worker: {x, y, heading, arm, jaw, t, path: [x0, y0, x1, y1, ...], figure?}
  // (path: the pen's points from the board's trace rows since the last frame)
  update(frame) {
    const t0 = performance.now();
    const p = frame.path || [];
    for (let i = 0; i + 1 < p.length; i += 2) this.penTo(p[i], p[i + 1]);
    if (this.path.length > PATH_MAX) this.cut();
    this.pose = { x: frame.x, y: frame.y, heading: frame.heading, arm: frame.arm,
                  jaw: frame.jaw, t: frame.t };
    if (frame.motor !== undefined) this.relays = { motor: frame.motor, aux: frame.aux };
    if (!this.start) this.start = { x: frame.x, y: frame.y, heading: frame.heading };
    if (frame.figure) { this.figure = frame.figure; this.figureDirty = true; }
    this.dirty = true;
    this.cost.update += performance.now() - t0;
  }

  // The pen: a straight stretch stays one segment (its last point moves on
  // while the robot keeps to the segment's first direction); every point
  // but the last is kept in a Path2D, extended, never rebuilt.
  penTo(x, y) {
    if (!this.start) this.start = { x, y, heading: this.pose.heading };
    const n = this.path.length, b = this.path[n - 1];
    if (b && Math.hypot(x - b[0], y - b[1]) < STEP_IN) return;
    const a = this.path[n - 2], d = this.direction;
    if (a && d && Math.abs((x - a[0]) * d[1] - (y - a[1]) * d[0]) < STRAIGHT_IN &&
        (x - b[0]) * d[0] + (y - b[1]) * d[1] > 0) { b[0] = x; b[1] = y; return; }
    if (b) {
      this.keep(n - 1);
      const len = Math.hypot(x - b[0], y - b[1]);
      this.direction = [(x - b[0]) / len, (y - b[1]) / len];
    }
    this.path.push([x, y]);
  }

  keep(i) {
    // point i joins the kept Path2D (all before it are there already)
    while (this.penLength <= i) {
      const [x, y] = this.path[this.penLength];
      this.penLength ? this.pen.lineTo(x, y) : this.pen.moveTo(x, y);
      this.penLength++;
    }
  }

  cut() {
    this.path.splice(0, this.path.length - PATH_MAX / 2);
    this.pen = new Path2D(); this.penLength = 0;
    this.keep(this.path.length - 2);
  }

  clear() {
    this.path = []; this.pen = new Path2D(); this.penLength = 0; this.direction = null;
    this.start = null; this.figure = null; this.dirty = this.figureDirty = true;
  }

  sized(canvas) {
    const r = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * r));
    const h = Math.max(1, Math.round(canvas.clientHeight * r));
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w; canvas.height = h;
      if (canvas === this.fig) this.figureDirty = true;
    }
    const g = canvas.getContext("2d");
    g.setTransform(r, 0, 0, r, 0, 0);
    return [g, canvas.clientWidth, canvas.clientHeight];
  }

  draw() {
    this.dirty = false;
    this.frames++;
    const t0 = performance.now();
    this.drawTop();
    const t1 = performance.now();
    this.cost.top += t1 - t0;
    this.cost.draws++;
    this.sized(this.fig);
    if (this.figureDirty) {
      this.figureDirty = false;
      this.drawFigure();
      this.cost.figure += performance.now() - t1;
      this.cost.figures++;
    }
  }

  // ------------------------------------------------------------ top view
  fit(w, h) {
    // the path's bounds and the robot, at least 6 feet across; ease toward it
    let x0 = this.pose.x, x1 = this.pose.x, y0 = this.pose.y, y1 = this.pose.y;
    const step = Math.max(1, Math.floor(this.path.length / 2000));
    for (let i = 0; i < this.path.length; i += step) {
      const [x, y] = this.path[i];
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
    }
    if (this.start) {
      x0 = Math.min(x0, this.start.x); x1 = Math.max(x1, this.start.x);
      y0 = Math.min(y0, this.start.y); y1 = Math.max(y1, this.start.y);
    }
    const span = Math.max(72, x1 - x0 + 48, (y1 - y0 + 48) * w / h);
    const target = (w / span) * this.zoom;
    this.scale += (target - this.scale) * 0.25;
    // follow: the robot stays inside the middle of the view
    const cx = this.zoom > 1 ? this.pose.x : (x0 + x1) / 2;
    const cy = this.zoom > 1 ? this.pose.y : (y0 + y1) / 2;
    this.centre.x += (cx - this.centre.x) * 0.25;
    this.centre.y += (cy - this.centre.y) * 0.25;
    if (Math.abs(target - this.scale) > 0.01 * target ||
        Math.hypot(cx - this.centre.x, cy - this.centre.y) > 0.1) this.dirty = true;
  }

  drawTop() {
    const [g, w, h] = this.sized(this.canvas);
    this.fit(w, h);
    const s = this.scale, c = this.centre;
    const px = (x) => w / 2 + (x - c.x) * s;
    const py = (y) => h / 2 - (y - c.y) * s;
    g.fillStyle = "#fbfaf6"; g.fillRect(0, 0, w, h);
    // the grid, a line a foot (a heavier one every 5 feet when zoomed out)
    const every = s * 12 < 8 ? 60 : 12;
    g.lineWidth = 1;
    for (let f = Math.floor((c.x - w / 2 / s) / every) * every; f <= c.x + w / 2 / s; f += every) {
      g.strokeStyle = f === 0 ? "#bbb" : "#e6e2d6";
      g.beginPath(); g.moveTo(px(f), 0); g.lineTo(px(f), h); g.stroke();
    }
    for (let f = Math.floor((c.y - h / 2 / s) / every) * every; f <= c.y + h / 2 / s; f += every) {
      g.strokeStyle = f === 0 ? "#bbb" : "#e6e2d6";
      g.beginPath(); g.moveTo(0, py(f)); g.lineTo(w, py(f)); g.stroke();
    }
    g.fillStyle = "#999"; g.font = "11px system-ui, sans-serif";
    g.fillText(every === 12 ? "grid: 1 ft" : "grid: 5 ft", 6, h - 6);
    // the start
    if (this.start) {
      g.strokeStyle = "#2a6"; g.lineWidth = 2;
      const sx = px(this.start.x), sy = py(this.start.y);
      g.beginPath(); g.arc(sx, sy, 6, 0, 2 * Math.PI); g.stroke();
      g.fillStyle = "#2a6"; g.fillText("start", sx + 8, sy - 8);
    }
    // the pen: the kept Path2D drawn in inches, then its last stretch to the robot
    if (this.path.length) {
      const r = window.devicePixelRatio || 1;
      g.save();
      g.setTransform(r * s, 0, 0, -r * s, r * (w / 2 - c.x * s), r * (h / 2 + c.y * s));
      g.strokeStyle = "#c0392b"; g.lineWidth = 2 / s; g.lineJoin = "round";
      if (this.penLength > 1) g.stroke(this.pen);
      g.beginPath();
      const last = this.path[Math.max(0, this.penLength - 1)];
      g.moveTo(last[0], last[1]);
      for (let i = this.penLength; i < this.path.length; i++) g.lineTo(this.path[i][0], this.path[i][1]);
      g.lineTo(this.pose.x, this.pose.y);
      g.stroke();
      g.restore();
    }
    this.drawRobot(g, px(this.pose.x), py(this.pose.y), s);
    this.drawArm(g, w);
  }

  drawRobot(g, x, y, s) {
    const p = this.pose, a = -p.heading * Math.PI / 180;
    this.robotPx = { x, y };
    g.save(); g.translate(x, y); g.rotate(a);
    const r = BODY_IN * s;
    g.fillStyle = "#dfe7f2cc"; g.strokeStyle = "#34495e"; g.lineWidth = 1.5;
    g.beginPath(); g.arc(0, 0, r, 0, 2 * Math.PI); g.fill(); g.stroke();
    for (const side of [-1, 1]) {                  // the wheels: green while relay and drive are on
      const bits = side < 0 ? LEFT_DRIVEN : RIGHT_DRIVEN;   // side -1: the left wheel (up, heading 0)
      g.fillStyle = (this.relays.motor & bits) === bits ? "#27ae60" : "#34495e";
      g.fillRect(-2.2 * s, side * TRACK_IN / 2 * s - 0.6 * s, 4.4 * s, 1.2 * s);
    }
    // the heading
    g.strokeStyle = "#34495e"; g.lineWidth = 2;
    g.beginPath(); g.moveTo(0, 0); g.lineTo(r * 0.8, 0); g.stroke();
    g.beginPath(); g.moveTo(r * 0.8, 0); g.lineTo(r * 0.6, -r * 0.12); g.lineTo(r * 0.6, r * 0.12);
    g.closePath(); g.fill();
    // the jaws, open by p.jaw inches, shaded by the arm's height (0 low .. 8 high)
    const half = (p.jaw / 2 + 0.3) * s, shade = Math.round(60 + 20 * (p.arm || 0));
    g.strokeStyle = "rgb(" + shade + "," + shade + "," + shade + ")";
    g.lineWidth = Math.max(2, 0.5 * s);
    for (const side of [-1, 1]) {
      g.beginPath(); g.moveTo(r, side * half); g.lineTo(r + 4 * s, side * half); g.stroke();
    }
    g.restore();
  }

  drawArm(g, w) {
    // the arm's height, 0 .. 8 in, as a gauge at the top right
    const p = this.pose, x = w - 26, top = 10, hgt = 60;
    g.strokeStyle = "#999"; g.lineWidth = 1; g.strokeRect(x, top, 10, hgt);
    const f = Math.max(0, Math.min(1, (p.arm || 0) / 8));
    g.fillStyle = "#7f8c8d"; g.fillRect(x, top + hgt * (1 - f), 10, hgt * f);
    g.fillStyle = "#555"; g.font = "11px system-ui, sans-serif"; g.textAlign = "right";
    g.fillText("arm " + (p.arm || 0).toFixed(2) + " in", x - 4, top + 10);
    g.fillText("jaw " + (p.jaw || 0).toFixed(2) + " in", x - 4, top + 24);
    g.textAlign = "left";
  }

  // -------------------------------------------------------------- Fig. 1
  drawFigure() {
    const [g, w, h] = this.sized(this.fig);
    g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
    const f = this.figure;
    g.font = "11px system-ui, sans-serif"; g.fillStyle = "#555";
    if (!f || !f.t.length) { g.fillText("Fig. 1: each wheel's speed and following error, live", 10, 16); return; }
    const t0 = f.t[0], t1 = Math.max(f.t[f.t.length - 1], t0 + 1);
    const L = 44, R = 8, half = h / 2;
    const tx = (t) => L + (t - t0) / (t1 - t0) * (w - L - R);
    const speeds = [...f.speed_left, ...f.speed_right, ...f.ref_left, ...f.ref_right];
    const vmax = Math.max(1, ...speeds.map(Math.abs)) * 1.1;
    const vmin = Math.min(0, ...speeds) * 1.1;
    const vy = (v) => 16 + (vmax - v) / (vmax - vmin || 1) * (half - 24);
    const emax = Math.max(f.limit * 1.2, ...[...f.ferr_left, ...f.ferr_right].map((p) => Math.abs(p[1])));
    const ey = (e) => half + 16 + (emax - e) / (2 * emax) * (half - 24);
    const axis = (y0, y1, label, lo, hi) => {
      g.strokeStyle = "#ccc"; g.lineWidth = 1;
      g.strokeRect(L, y0, w - L - R, y1 - y0);
      g.fillStyle = "#555"; g.fillText(label, L, y0 - 3);
      g.fillText(hi, 2, y0 + 10); g.fillText(lo, 2, y1);
    };
    axis(16, half - 8, "wheel speed, in/s (dashed: commanded; ▲ acceleration ends, ▼ deceleration begins)",
         vmin.toFixed(0), vmax.toFixed(0));
    axis(half + 16, h - 8, "following error, counts (red: FERR-LIMIT " + f.limit + ")",
         (-emax).toFixed(0), emax.toFixed(0));
    const line = (ts, vs, colour, dash, y) => {
      g.strokeStyle = colour; g.setLineDash(dash); g.lineWidth = 1.2;
      g.beginPath();
      for (let i = 0; i < ts.length; i++) {
        if (vs[i] === null) continue;
        i ? g.lineTo(tx(ts[i]), y(vs[i])) : g.moveTo(tx(ts[i]), y(vs[i]));
      }
      g.stroke(); g.setLineDash([]);
    };
    for (const wheel of ["left", "right"]) {
      line(f.t, f["speed_" + wheel], COLOURS[wheel], [], vy);
      line(f.t, f["ref_" + wheel], COLOURS[wheel], [5, 3], vy);
      const e = f["ferr_" + wheel];
      line(e.map((p) => p[0]), e.map((p) => p[1]), COLOURS[wheel], [], ey);
    }
    g.strokeStyle = "#c00"; g.setLineDash([4, 3]);
    for (const lim of [f.limit, -f.limit]) {
      g.beginPath(); g.moveTo(L, ey(lim)); g.lineTo(w - R, ey(lim)); g.stroke();
    }
    g.setLineDash([]);
    const marks = (pts, colour, up) => {
      g.fillStyle = colour;
      for (const [t, v] of pts) {
        const x = tx(t), y = vy(v), d = up ? -1 : 1;
        g.beginPath(); g.moveTo(x, y + 5 * d); g.lineTo(x - 4, y - 3 * d); g.lineTo(x + 4, y - 3 * d); g.fill();
      }
    };
    marks(f.acc, "green", true);
    marks(f.dec, "purple", false);
    for (const c of f.cuts) { g.fillStyle = "#999"; g.fillText("≈", tx(c) - 3, half - 10); }
    g.fillStyle = "#555";
    g.fillText("t " + t1.toFixed(1) + " s (idle stretches cut to 2 s)", w - R - 190, h - 12);
    g.fillStyle = COLOURS.left; g.fillText("left", w - R - 70, 28);
    g.fillStyle = COLOURS.right; g.fillText("right", w - R - 40, 28);
  }

  // What the tests and course pages read: where the robot is drawn.
  state() {
    return { frames: this.frames, robot: { ...this.robotPx }, pose: { ...this.pose }, relays: { ...this.relays },
             path: this.path.length, scale: this.scale, cost: { ...this.cost } };
  }
}

