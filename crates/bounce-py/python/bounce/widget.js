// The front-end half of `bounce.widget.View` (an anywidget module: JupyterLab, Notebook 7,
// VS Code). Draws the discs the Python side sends as binary buffers (WebGL point sprites on a
// GPU; elsewhere, or for discs too large for a sprite, a CPU raster on a 2D canvas), the
// obstacles on a 2D overlay, the speed histogram against Maxwell–Boltzmann, and play, pause
// and step.
//
// What arrives (traits, set together by Python): `positions` (f32 x, y a disc), `radii` (f32),
// `shades` (u8 a disc: 0–255 along the colour ramp, speed or radius as `colour_by` chose),
// `bounds` [xmin, ymin, xmax, ymax], `obstacles` (segments and pegs), `frame` (step, time,
// discs, histogram). Controls go back as the synced `playing` and custom messages
// `{type: "step"}` and `{type: "tick"}`: while playing, the page keeps two frames asked for
// ahead, each arrival asking for one more, so frames never queue faster than they arrive.

// The stops of `bounce_scenario::colour::ramp` (dark blue, teal, green, yellow): the same
// colours as the desktop viewer, PNG frames and the web page.
const STOPS = [
  [59, 76, 192],
  [40, 140, 200],
  [60, 180, 140],
  [170, 210, 60],
  [250, 230, 40],
];

/// The ramp's colour for a shade 0–255, as [r, g, b] in 0–255.
export function ramp(shade) {
  const t = (Math.min(Math.max(shade, 0), 255) / 255) * (STOPS.length - 1);
  const k = Math.min(Math.floor(t), STOPS.length - 2);
  const f = t - k;
  return [0, 1, 2].map((c) => Math.round(STOPS[k][c] + (STOPS[k + 1][c] - STOPS[k][c]) * f));
}

const BACKGROUND = [24, 26, 32];
const OBSTACLE = "#d8d8d8";

/// A typed view of a binary trait (ipywidgets hands bytes over as a DataView), copied when
/// the buffer's offset does not suit the element size.
function typed(value, Type) {
  if (!value) return new Type(0);
  let buffer, offset, length;
  if (value instanceof ArrayBuffer) {
    [buffer, offset, length] = [value, 0, value.byteLength];
  } else if (ArrayBuffer.isView(value)) {
    [buffer, offset, length] = [value.buffer, value.byteOffset, value.byteLength];
  } else {
    return new Type(0);
  }
  const n = Math.floor(length / Type.BYTES_PER_ELEMENT);
  if (offset % Type.BYTES_PER_ELEMENT === 0) return new Type(buffer, offset, n);
  return new Type(buffer.slice(offset, offset + n * Type.BYTES_PER_ELEMENT));
}

/// World to canvas pixels: the bounds fitted into the canvas, centred, y up.
function fit(bounds, width, height) {
  const [x0, y0, x1, y1] = bounds;
  const w = Math.max(x1 - x0, 1e-12);
  const h = Math.max(y1 - y0, 1e-12);
  const scale = Math.min(width / w, height / h);
  const ox = (width - w * scale) / 2 - x0 * scale;
  const oy = (height - h * scale) / 2 + y1 * scale;
  return { scale, ox, oy, x: (x) => ox + x * scale, y: (y) => oy - y * scale };
}

const VERTEX = `
attribute vec2 a_position;
attribute float a_radius;
attribute float a_shade;
uniform vec2 u_scale;
uniform vec2 u_offset;
uniform float u_pixels;
varying vec3 v_colour;
varying float v_size;
vec3 ramp(float t) {
  vec3 s0 = vec3(59.0, 76.0, 192.0) / 255.0;
  vec3 s1 = vec3(40.0, 140.0, 200.0) / 255.0;
  vec3 s2 = vec3(60.0, 180.0, 140.0) / 255.0;
  vec3 s3 = vec3(170.0, 210.0, 60.0) / 255.0;
  vec3 s4 = vec3(250.0, 230.0, 40.0) / 255.0;
  float u = clamp(t, 0.0, 1.0) * 4.0;
  if (u < 1.0) return mix(s0, s1, u);
  if (u < 2.0) return mix(s1, s2, u - 1.0);
  if (u < 3.0) return mix(s2, s3, u - 2.0);
  return mix(s3, s4, u - 3.0);
}
void main() {
  gl_Position = vec4(a_position * u_scale + u_offset, 0.0, 1.0);
  v_size = max(2.0 * a_radius * u_pixels, 1.0);
  gl_PointSize = v_size;
  v_colour = ramp(a_shade);
}`;

const FRAGMENT = `
precision mediump float;
varying vec3 v_colour;
varying float v_size;
void main() {
  vec2 c = gl_PointCoord * 2.0 - 1.0;
  // Discs under two pixels across are drawn as whole pixels rather than vanishing.
  if (v_size > 2.0 && dot(c, c) > 1.0) discard;
  gl_FragColor = vec4(v_colour, 1.0);
}`;

/// The WebGL renderer, or null where WebGL is missing.
function webgl(canvas) {
  const gl = canvas.getContext("webgl", { antialias: false, preserveDrawingBuffer: true });
  if (!gl) return null;
  const shader = (type, text) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, FRAGMENT));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const attribute = (name) => gl.getAttribLocation(program, name);
  const buffers = { position: gl.createBuffer(), radius: gl.createBuffer(), shade: gl.createBuffer() };
  const uniform = (name) => gl.getUniformLocation(program, name);
  const maxPoint = gl.getParameter(gl.ALIASED_POINT_SIZE_RANGE)[1];
  return {
    kind: "webgl",
    context: gl,
    maxPoint,
    draw(view, data) {
      const { width, height } = canvas;
      gl.viewport(0, 0, width, height);
      gl.clearColor(...BACKGROUND.map((c) => c / 255), 1);
      gl.clear(gl.COLOR_BUFFER_BIT);
      const n = data.radii.length;
      if (n === 0) return;
      gl.useProgram(program);
      const bind = (buffer, values, name, size, type, normalised) => {
        gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
        gl.bufferData(gl.ARRAY_BUFFER, values, gl.DYNAMIC_DRAW);
        const at = attribute(name);
        gl.enableVertexAttribArray(at);
        gl.vertexAttribPointer(at, size, type, normalised, 0, 0);
      };
      bind(buffers.position, data.positions, "a_position", 2, gl.FLOAT, false);
      bind(buffers.radius, data.radii, "a_radius", 1, gl.FLOAT, false);
      bind(buffers.shade, data.shades, "a_shade", 1, gl.UNSIGNED_BYTE, true);
      // Pixels to clip space: x' = 2 (ox + s x) / W − 1, y' = 1 − 2 (oy − s y) / H.
      gl.uniform2f(uniform("u_scale"), (2 * view.scale) / width, (2 * view.scale) / height);
      gl.uniform2f(uniform("u_offset"), (2 * view.ox) / width - 1, 1 - (2 * view.oy) / height);
      gl.uniform1f(uniform("u_pixels"), view.scale);
      gl.drawArrays(gl.POINTS, 0, n);
    },
  };
}

/// The raster renderer: discs filled pixel by pixel on the CPU into one image a frame (a
/// pixel is the disc's when its centre is inside), put on a 2D canvas. Its cost is the discs
/// plus the pixels they cover, so it beats software WebGL (SwiftShader, llvmpipe), whose
/// cost per point sprite dominates at 10^5 discs.
function raster(canvas) {
  const ctx = canvas.getContext("2d");
  // One RGBA word a colour, in the byte order of the machine (ImageData is RGBA in memory).
  const little = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;
  const word = ([r, g, b]) =>
    little ? ((255 << 24) | (b << 16) | (g << 8) | r) >>> 0 : ((r << 24) | (g << 16) | (b << 8) | 255) >>> 0;
  const palette = new Uint32Array(256).map((_, s) => word(ramp(s)));
  const background = word(BACKGROUND);
  let image = null;
  let pixels = null;
  return {
    kind: "raster",
    draw(view, data) {
      const { width, height } = canvas;
      if (!image || image.width !== width || image.height !== height) {
        image = ctx.createImageData(width, height);
        pixels = new Uint32Array(image.data.buffer);
      }
      pixels.fill(background);
      const { positions, radii, shades } = data;
      for (let i = 0; i < radii.length; i++) {
        const cx = view.x(positions[2 * i]);
        const cy = view.y(positions[2 * i + 1]);
        const r = radii[i] * view.scale;
        const colour = palette[shades[i]];
        if (r < 0.75) {
          // Smaller than a pixel: the pixel under the centre, so no disc vanishes.
          const px = Math.floor(cx);
          const py = Math.floor(cy);
          if (px >= 0 && px < width && py >= 0 && py < height) pixels[py * width + px] = colour;
          continue;
        }
        const y0 = Math.max(Math.ceil(cy - r - 0.5), 0);
        const y1 = Math.min(Math.floor(cy + r - 0.5), height - 1);
        for (let py = y0; py <= y1; py++) {
          const dy = py + 0.5 - cy;
          const half = Math.sqrt(Math.max(r * r - dy * dy, 0));
          const x0 = Math.max(Math.ceil(cx - half - 0.5), 0);
          const x1 = Math.min(Math.floor(cx + half - 0.5), width - 1);
          if (x1 >= x0) pixels.fill(colour, py * width + x0, py * width + x1 + 1);
        }
      }
      ctx.putImageData(image, 0, 0);
    },
  };
}

/// True where the WebGL context draws in software (no GPU): there the raster renderer wins.
function software(gl) {
  const info = gl.getExtension("WEBGL_debug_renderer_info");
  const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
  return /swiftshader|llvmpipe|softpipe|software/i.test(name);
}

/// Segments and pegs, on the transparent overlay.
function drawObstacles(overlay, view, obstacles) {
  const ctx = overlay.getContext("2d");
  ctx.clearRect(0, 0, overlay.width, overlay.height);
  ctx.strokeStyle = OBSTACLE;
  ctx.fillStyle = OBSTACLE;
  ctx.lineWidth = 2;
  for (const o of obstacles || []) {
    ctx.beginPath();
    if (o.kind === "segment") {
      ctx.moveTo(view.x(o.a[0]), view.y(o.a[1]));
      ctx.lineTo(view.x(o.b[0]), view.y(o.b[1]));
      ctx.stroke();
    } else {
      ctx.arc(view.x(o.centre[0]), view.y(o.centre[1]), Math.max(o.radius * view.scale, 1), 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}

/// The speed histogram (bars) and the Maxwell–Boltzmann curve (red).
function drawHistogram(canvas, histogram) {
  const ctx = canvas.getContext("2d");
  const { width, height } = canvas;
  ctx.fillStyle = "#ffffff";
  ctx.fillRect(0, 0, width, height);
  if (!histogram || !histogram.density || histogram.density.length === 0) return;
  const { density, width: bin, curve } = histogram;
  const vMax = Math.max(density.length * bin, curve.length ? curve[curve.length - 1][0] : 0, 1e-12);
  const dMax = Math.max(...density, ...curve.map((p) => p[1]), 1e-12) * 1.1;
  const pad = 18;
  const px = (v) => pad + (v / vMax) * (width - 2 * pad);
  const py = (d) => height - pad - (d / dMax) * (height - 2 * pad);
  ctx.fillStyle = "rgb(120,160,220)";
  density.forEach((d, k) => {
    const x0 = px(k * bin);
    ctx.fillRect(x0, py(d), Math.max(px((k + 1) * bin) - x0 - 1, 1), py(0) - py(d));
  });
  ctx.strokeStyle = "rgb(220,40,40)";
  ctx.lineWidth = 2;
  ctx.beginPath();
  curve.forEach(([v, d], k) => (k === 0 ? ctx.moveTo(px(v), py(d)) : ctx.lineTo(px(v), py(d))));
  ctx.stroke();
  ctx.fillStyle = "#333";
  ctx.font = "11px sans-serif";
  ctx.fillText(`speed (kT = ${Number(histogram.kt).toPrecision(4)})`, pad, height - 4);
  ctx.fillText("bars: discs · red: Maxwell–Boltzmann", pad, 12);
}

function button(label, title) {
  const b = document.createElement("button");
  b.textContent = label;
  b.title = title;
  b.style.cssText = "margin-right:6px;padding:2px 10px;cursor:pointer";
  return b;
}

function render({ model, el }) {
  const root = document.createElement("div");
  root.className = "bounce-view";
  root.style.cssText = "font:12px sans-serif;display:inline-block";
  const bar = document.createElement("div");
  bar.style.cssText = "margin-bottom:4px;display:flex;align-items:center";
  const play = button("play", "play: Python steps the world while the page draws");
  play.className = "bounce-play";
  const step = button("step", "step once (`every` steps)");
  step.className = "bounce-step";
  const status = document.createElement("span");
  status.className = "bounce-status";
  bar.append(play, step, status);
  const row = document.createElement("div");
  row.style.cssText = "display:flex;gap:8px;align-items:flex-start";
  const stack = document.createElement("div");
  stack.style.cssText = "position:relative";
  const discs = document.createElement("canvas");
  discs.className = "bounce-discs";
  const overlay = document.createElement("canvas");
  overlay.style.cssText = "position:absolute;left:0;top:0;pointer-events:none";
  stack.append(discs, overlay);
  const histogram = document.createElement("canvas");
  histogram.className = "bounce-histogram";
  row.append(stack, histogram);
  root.append(bar, row);
  el.append(root);

  let renderer = null;
  const fresh = () => {
    const c = document.createElement("canvas");
    c.className = "bounce-discs";
    stack.replaceChild(c, stack.firstChild);
    return c;
  };
  // "auto": WebGL on a GPU, the raster where WebGL is missing or drawn in software;
  // "webgl" and "raster" ask for one (WebGL still falls back where it is missing).
  const choose = () => {
    const want = model.get("renderer");
    if (renderer && (want === "auto" || want === renderer.kind)) return;
    // A canvas keeps the first context it gave, so each renderer gets a fresh one.
    let gl = want === "raster" ? null : webgl(fresh());
    if (gl && want === "auto" && software(gl.context)) gl = null;
    renderer = gl || raster(fresh());
  };

  // What the test harness (and a curious user, through `el.bounce`) can read.
  const stats = { draws: 0, renderer: "", drawTimes: [], canvas: () => stack.firstChild };
  el.bounce = stats;
  let pending = false;
  // While playing, this many frames are asked for ahead: Python steps the next one while the
  // page draws this one and the messages travel, yet at most WINDOW frames are ever queued.
  const WINDOW = 2;
  let asked = 0;
  const ask = () => {
    while (model.get("playing") && asked < WINDOW) {
      asked += 1;
      model.send({ type: "tick" });
    }
  };

  const size = () => {
    const bounds = model.get("bounds");
    const width = model.get("width");
    const aspect = (bounds[3] - bounds[1]) / Math.max(bounds[2] - bounds[0], 1e-12);
    const height = Math.round(Math.min(Math.max(width * aspect, 120), 2 * width));
    return [width, height];
  };

  const draw = () => {
    pending = false;
    const t0 = performance.now();
    choose();
    const [width, height] = size();
    const target = stack.firstChild;
    for (const c of [target, overlay]) {
      if (c.width !== width || c.height !== height) {
        c.width = width;
        c.height = height;
        c.style.width = `${width}px`;
        c.style.height = `${height}px`;
      }
    }
    const view = fit(model.get("bounds"), width, height);
    const data = {
      positions: typed(model.get("positions"), Float32Array),
      radii: typed(model.get("radii"), Float32Array),
      shades: typed(model.get("shades"), Uint8Array),
    };
    const n = Math.min(data.radii.length, data.positions.length / 2, data.shades.length);
    data.radii = data.radii.subarray(0, n);
    let active = renderer;
    if (active.kind === "webgl") {
      let biggest = 0;
      for (let i = 0; i < n; i++) biggest = Math.max(biggest, data.radii[i]);
      if (2 * biggest * view.scale > active.maxPoint) {
        // Point sprites stop at the driver's size limit: such a view goes to the 2D canvas.
        model.set("renderer", "raster");
        choose();
        active = renderer;
      }
    }
    active.draw(view, data);
    drawObstacles(overlay, view, model.get("obstacles"));
    const frame = model.get("frame") || {};
    histogram.style.display = model.get("histogram") ? "" : "none";
    if (model.get("histogram")) {
      histogram.width = 260;
      histogram.height = Math.min(height, 200);
      drawHistogram(histogram, frame.histogram);
    }
    stats.draws += 1;
    stats.renderer = active.kind;
    stats.drawTimes.push(performance.now() - t0);
    if (stats.drawTimes.length > 120) stats.drawTimes.shift();
    const playing = model.get("playing");
    play.textContent = playing ? "pause" : "play";
    status.textContent =
      `step ${frame.step ?? 0} · t = ${Number(frame.time ?? 0).toPrecision(5)} · ` +
      `${n} discs · ${active.kind}`;
  };
  const later = () => {
    if (!pending) {
      pending = true;
      requestAnimationFrame(draw);
    }
  };

  play.addEventListener("click", () => {
    model.set("playing", !model.get("playing"));
    model.save_changes();
    asked = 0;
    ask();
    later();
  });
  step.addEventListener("click", () => model.send({ type: "step" }));
  const arrived = () => {
    asked = Math.max(asked - 1, 0);
    ask();
  };
  const names = ["frame", "bounds", "obstacles", "width", "renderer", "histogram", "playing"];
  for (const name of names) model.on(`change:${name}`, later);
  model.on("change:frame", arrived);
  model.on("change:playing", ask);
  later();
  return () => {
    for (const name of names) model.off(`change:${name}`, later);
    model.off("change:frame", arrived);
    model.off("change:playing", ask);
  };
}

export default { render };
