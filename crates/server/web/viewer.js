// raystage's viewer page (docs/guide/browser.md): the progressive stream of one scene on a
// canvas, the camera moved as the egui viewer moves it, the stream's settings, picking, glTF
// uploads and the animation timeline, all through the server's HTTP API and its stream
// (api/stream.md). Served by the server itself (crates/server/src/routes/web.rs); no build step.
'use strict';

// ---------------------------------------------------------------------------------------------
// The camera: orbit, pan and zoom around the target, as crates/client/src/orbit.rs does them
// (its constants and its arithmetic, so that a drag moves the camera the same in both viewers).
// Distances on screen are CSS pixels, which are egui's points.

/** Radians of orbit per point of motion: half a turn for about 314 points. */
const ORBIT_RADIANS_PER_POINT = 0.01;
/** Distance factor per point of scroll: 100 points bring the eye 1/e² ≈ 14 % closer. */
const ZOOM_PER_POINT = 0.002;
/** The closest the view direction comes to `up` (radians). */
const POLE_MARGIN = 0.01;

const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.sqrt(dot(a, a));
const clamp = (x, low, high) => Math.min(Math.max(x, low), high);

/** `a` made unit length, or null where it has none (zero or not finite), as glam's try_normalize. */
function normalize(a) {
  const reciprocal = 1 / length(a);
  return Number.isFinite(reciprocal) && reciprocal > 0 ? scale(a, reciprocal) : null;
}

/** `v` turned by `angle` radians about the unit vector `axis`, right-handed (Rodrigues' formula:
 *  what glam's `Quat::from_axis_angle(axis, angle) * v` computes). */
function rotate(v, axis, angle) {
  const c = Math.cos(angle), s = Math.sin(angle);
  return add(add(scale(v, c), scale(cross(axis, v), s)), scale(axis, dot(axis, v) * (1 - c)));
}

/** A camera that orbits its target. */
class Orbit {
  /** The orbit of a camera as the server describes it (`CameraJson`). */
  constructor(camera) {
    this.eye = camera.eye.slice();
    this.target = camera.target.slice();
    this.up = camera.up.slice();
    this.fovYDegrees = camera.fov_y_degrees;
  }

  /** The change to send for this camera. */
  patch() {
    return { eye: this.eye, target: this.target };
  }

  upAxis() {
    return normalize(this.up) ?? [0, 1, 0];
  }

  /** Orbits by a motion of (dx, dy) points (y down): a drag to the right takes the eye left
   *  around the target, a drag down raises it, stopping short of the poles. */
  orbit(dx, dy) {
    const up = this.upAxis();
    const offset = sub(this.eye, this.target);
    const distance = length(offset);
    if (!(distance > 0) || !Number.isFinite(distance)) return;
    const yawed = rotate(offset, up, -dx * ORBIT_RADIANS_PER_POINT);
    const polar = Math.acos(clamp(dot(normalize(yawed), up), -1, 1));
    const newPolar = clamp(polar - dy * ORBIT_RADIANS_PER_POINT, POLE_MARGIN, Math.PI - POLE_MARGIN);
    const right = normalize(cross(up, yawed));
    const turned = right ? rotate(yawed, right, newPolar - polar) : yawed;
    this.eye = add(this.target, scale(normalize(turned), distance));
  }

  /** Pans by a motion of (dx, dy) points in a view `height` points high: eye and target move
   *  together so that the point at the target's depth follows the pointer. */
  pan(dx, dy, height) {
    const forward = sub(this.target, this.eye);
    const distance = length(forward);
    const right = normalize(cross(forward, this.upAxis()));
    if (!right) return;
    const screenUp = normalize(cross(right, forward));
    const worldPerPoint = (2 * distance * Math.tan((this.fovYDegrees * Math.PI) / 360)) / Math.max(height, 1);
    const delta = scale(add(scale(right, -dx), scale(screenUp, dy)), worldPerPoint);
    this.eye = add(this.eye, delta);
    this.target = add(this.target, delta);
  }

  /** Zooms by `scroll` points (positive: closer). */
  zoom(scroll) {
    const offset = sub(this.eye, this.target);
    const distance = Math.max(length(offset) * Math.exp(-scroll * ZOOM_PER_POINT), 1e-4);
    const direction = normalize(offset);
    if (direction) this.eye = add(this.target, scale(direction, distance));
  }
}

// ---------------------------------------------------------------------------------------------
// The access token and HTTP. The token is kept for the tab only (sessionStorage) and sent on
// every request, and as `?token=` on the stream, where browsers cannot set headers.

const TOKEN_KEY = 'raystage.token';
let token = sessionStorage.getItem(TOKEN_KEY);

/** The server wants a token the page does not have (or has wrong). */
class Unauthorized extends Error {}

const $ = (id) => document.getElementById(id);

/** `path` fetched with the token; a refused token asks for another, other failures throw the
 *  server's message. */
async function api(path, options = {}) {
  const headers = new Headers(options.headers);
  if (token) headers.set('Authorization', `Bearer ${token}`);
  const response = await fetch(path, { ...options, headers });
  if (response.status === 401) {
    askForToken();
    throw new Unauthorized('unauthorized');
  }
  if (!response.ok) throw new Error(await errorMessage(response.status, await response.text()));
  return response;
}

const getJson = async (path) => (await api(path)).json();

/** What an error response says: the API's `{"error": {"message"}}`, else its status. */
function errorMessage(status, text) {
  try {
    return JSON.parse(text).error.message;
  } catch {
    return `the server answered ${status}`;
  }
}

/** Shows the token form, saying why nothing loads. */
function askForToken() {
  closeStream();
  const reason = token
    ? 'The server refused this token: enter the right one. Nothing loads without it.'
    : 'This server needs an access token. Nothing loads without it.';
  $('auth-reason').textContent = reason;
  $('auth').hidden = false;
  say(reason);
  $('token').focus();
}

$('auth').addEventListener('submit', (event) => {
  event.preventDefault();
  token = $('token').value.trim();
  sessionStorage.setItem(TOKEN_KEY, token);
  $('auth').hidden = true;
  start();
});

/** Shows `text` over the image ('' clears it). */
function say(text) {
  $('message').textContent = text;
}

/** Shows what went wrong, unless it was a token the form already asks for. */
function report(error) {
  if (!(error instanceof Unauthorized)) say(error.message);
}

// ---------------------------------------------------------------------------------------------
// Scenes.

let sceneId = null;
/** The camera the pointer moves: the scene's when it opens, then ours. */
let orbit = null;

/** Lists the scenes and opens the one the address names (`#scene=N`), else the first. */
async function start() {
  try {
    const scenes = await getJson('/scenes');
    listScenes(scenes);
    const named = Number(new URLSearchParams(location.hash.slice(1)).get('scene'));
    const chosen = scenes.find((s) => s.id === named) ?? scenes[0];
    if (!chosen) {
      say('The server has no scenes: drop a glTF file here, or start the server with --demo.');
      return;
    }
    await openScene(chosen.id);
  } catch (error) {
    report(error);
  }
}

function listScenes(scenes) {
  const list = $('scene');
  list.replaceChildren(...scenes.map((s) => new Option(`${s.id} · ${s.origin} · ${s.triangles.toLocaleString('en')} triangles`, s.id)));
  list.disabled = scenes.length === 0;
  if (sceneId !== null) list.value = sceneId;
}

$('scene').addEventListener('change', () => openScene(Number($('scene').value)).catch(report));

/** Opens scene `id`: its camera, objects, instances and animations, then its stream. */
async function openScene(id) {
  closeStream();
  clearFrame();
  sceneId = id;
  history.replaceState(null, '', `#scene=${id}`);
  $('scene').value = id;
  select(null);
  say('Loading the scene…');
  const [info, animations] = await Promise.all([showScene(id), getJson(`/scenes/${id}/animations`)]);
  orbit = new Orbit(info.camera);
  // A scene never posed has no clock yet (404).
  const clock = animations.length > 0 ? await getJson(`/scenes/${id}/clock`).catch(() => null) : null;
  showTimeline(animations, clock);
  openStream();
}

/** Fills the scene panel: its summary, objects and instances; returns the summary
 *  (`SceneInfo`). */
async function showScene(id) {
  const [info, objects, instances] = await Promise.all([getJson(`/scenes/${id}`), getJson(`/scenes/${id}/objects`), getJson(`/scenes/${id}/instances`)]);
  $('scene-summary').textContent =
    `${info.origin}: ${info.objects} objects, ${info.instances} instances, ${info.triangles.toLocaleString('en')} triangles, ${info.lights} lights`;
  fillTable('objects', objects, (o) => [o.id, o.kind, o.triangles.toLocaleString('en')]);
  fillTable('instances', instances, (i) => {
    const button = document.createElement('button');
    button.type = 'button';
    button.textContent = 'select';
    button.setAttribute('aria-label', `select instance ${i.id}`);
    button.addEventListener('click', () => select({ instance: i.id, object: i.object }));
    return [i.id, i.object, button];
  });
  markSelected();
  return info;
}

/** Rows shown in a table at most: a scene may have a million instances. */
const MAX_ROWS = 500;

function fillTable(id, items, cells) {
  const rows = items.slice(0, MAX_ROWS).map((item) => {
    const row = document.createElement('tr');
    row.dataset.id = item.id;
    for (const cell of cells(item)) row.insertCell().append(cell);
    return row;
  });
  if (items.length > MAX_ROWS) {
    const more = document.createElement('tr');
    more.insertCell().textContent = `and ${(items.length - MAX_ROWS).toLocaleString('en')} more`;
    rows.push(more);
  }
  $(id).tBodies[0].replaceChildren(...rows);
}

$('refresh').addEventListener('click', async () => {
  try {
    listScenes(await getJson('/scenes'));
    if (sceneId !== null) await showScene(sceneId);
  } catch (error) {
    report(error);
  }
});

// ---------------------------------------------------------------------------------------------
// The stream: the frames of the scene, sized to the view, and the messages that change it.

const canvas = $('frame');
const context = canvas.getContext('2d', { alpha: false });
const view = $('view');

let socket = null;
let nextRequest = 1;
/** What each request in flight is answered with: request → function(reply). */
const answers = new Map();
/** The `frame` message whose image comes next. */
let frameMessage = null;
/** The statistics of the frame on the canvas. */
let shown = null;
/** The newest image not yet decoded (older ones are dropped), and whether one is decoding. */
let newest = null;
let decoding = false;
/** Images received in the last second: when, and how many bytes, for the rate. */
const received = [];

/** The image size for the view: its CSS pixels times the device pixel ratio times the chosen
 *  resolution. */
function wantedSize() {
  const factor = (window.devicePixelRatio || 1) * Number($('scale').value);
  return [clamp(Math.round(view.clientWidth * factor), 16, 8192), clamp(Math.round(view.clientHeight * factor), 16, 8192)];
}

/** The stream's settings as the controls have them, in the names the stream takes. */
function controlSettings() {
  const settings = {
    max_samples: Number($('max-samples').value),
    exposure: Number($('exposure').value),
    tonemap: $('tonemap').value,
    encoding: $('encoding').value,
    quality: Number($('quality').value),
  };
  if ($('integrator').value) settings.integrator = $('integrator').value;
  return settings;
}

/** The size last asked for. */
let sentSize = null;

function openStream() {
  closeStream();
  const [width, height] = (sentSize = wantedSize());
  const query = new URLSearchParams({ width, height, ...controlSettings() });
  if (token) query.set('token', token);
  const path = `/scenes/${sceneId}/stream?${query}`;
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  const stream = new WebSocket(`${scheme}://${location.host}${path}`);
  let opened = false;
  stream.binaryType = 'blob';
  stream.onopen = () => {
    opened = true;
    say('Waiting for the first frame…');
  };
  stream.onmessage = (event) => (typeof event.data === 'string' ? onMessage(JSON.parse(event.data)) : onImage(event.data));
  stream.onclose = async (event) => {
    if (socket !== stream) return;
    socket = null;
    const why = event.reason || (opened ? '' : await whyRefused(path));
    say(`The stream closed${why ? `: ${why}` : ''}. Change a setting or choose the scene again to reconnect.`);
  };
  socket = stream;
}

/** Why the server refused to open the stream at `path`: a browser's WebSocket does not tell,
 *  but the same request without the upgrade gets the server's error (api/stream.md), which names
 *  the upgrade only where the stream would have opened. */
async function whyRefused(path) {
  try {
    const response = await fetch(path, { headers: token ? { Authorization: `Bearer ${token}` } : {} });
    const { error } = await response.json();
    return error.field === 'upgrade' ? '' : error.message;
  } catch {
    return '';
  }
}

function closeStream() {
  if (socket) {
    const old = socket;
    socket = null;
    // One still connecting closes once it opens: closed before, Firefox logs an error (that it
    // could not connect) for a connection the page gave up itself, as when two settings change
    // in a row.
    if (old.readyState === WebSocket.CONNECTING) old.onopen = () => old.close();
    else old.close();
  }
  answers.clear();
  cameraQueue.inFlight = null;
  latencyProbe = null;
  frameMessage = null;
  newest = null;
}

/** Sends a `settings` change; a stream that is not open opens anew with the controls' settings,
 *  which include the change. */
function changeSettings(change) {
  if (socket?.readyState === WebSocket.OPEN) send({ type: 'settings', ...change });
  else if (sceneId !== null) openStream();
}

/** Sends `message` on the stream with a new request number; `answer` gets the reply. */
function send(message, answer) {
  if (!socket || socket.readyState !== WebSocket.OPEN) return null;
  const request = nextRequest++;
  if (answer) answers.set(request, answer);
  socket.send(JSON.stringify({ ...message, request }));
  return request;
}

function onMessage(message) {
  switch (message.type) {
    case 'frame':
      frameMessage = message;
      followFrame(message);
      break;
    case 'result':
    case 'error': {
      const answer = answers.get(message.request);
      answers.delete(message.request);
      answer?.(message);
      if (message.type === 'error') say(message.error.message);
      break;
    }
  }
}

function onImage(blob) {
  const now = performance.now();
  received.push({ at: now, bytes: blob.size });
  if (frameMessage) newest = { blob, frame: frameMessage };
  frameMessage = null;
  if (!decoding) decodeNewest();
}

/** Decodes and draws the newest image until none is waiting: a slow decoder skips images, it
 *  never queues them. */
async function decodeNewest() {
  decoding = true;
  while (newest) {
    const { blob, frame } = newest;
    newest = null;
    try {
      const bitmap = await createImageBitmap(blob);
      draw(bitmap, frame);
      bitmap.close();
    } catch (error) {
      say(`A frame could not be decoded: ${error.message}`);
    }
  }
  decoding = false;
}

function draw(bitmap, frame) {
  if (canvas.width !== bitmap.width || canvas.height !== bitmap.height) {
    canvas.width = bitmap.width;
    canvas.height = bitmap.height;
  }
  context.drawImage(bitmap, 0, 0);
  shown = frame;
  // For scripts (and the tests): which frame the canvas shows.
  canvas.dataset.seq = frame.seq;
  canvas.dataset.sceneVersion = frame.scene_version;
  canvas.dataset.samples = frame.samples;
  say('');
  measureLatency(frame);
  showStats(frame);
  if (selection && highlighted !== frame.scene_version) highlight();
}

/** Clears the canvas of another scene's image. */
function clearFrame() {
  context.clearRect(0, 0, canvas.width, canvas.height);
  shown = null;
  for (const key of ['seq', 'sceneVersion', 'samples']) delete canvas.dataset[key];
}

function showStats(frame) {
  $('stat-image').textContent = `${frame.width}×${frame.height}, ${frame.integrator}`;
  $('stat-samples').textContent = `${frame.samples} of ${Number($('max-samples').value)} per pixel${frame.converged ? ', converged' : ''}`;
  $('stat-pass').textContent = `${frame.pass_samples} spp in ${(frame.pass_seconds * 1000).toFixed(0)} ms, ${frame.mrays_per_second.toFixed(1)} Mrays/s`;
  $('stat-rays').textContent = frame.rays.total.toLocaleString('en');
  $('stat-effects').textContent = frame.effects.join(', ') || 'none';
  $('stat-encoding').textContent = `${frame.encoding.toUpperCase()} in ${(frame.encode_seconds * 1000).toFixed(1)} ms`;
  showRate();
}

/** The frames and bytes received in the last second; shown every second too, so that a
 *  converged image, which gets no frames, shows none. */
function showRate() {
  const now = performance.now();
  while (received.length && received[0].at < now - 1000) received.shift();
  const kilobytes = received.reduce((sum, r) => sum + r.bytes, 0) / 1000;
  $('stat-rate').textContent = `${received.length} frames/s, ${kilobytes.toFixed(0)} kB/s`;
}
setInterval(showRate, 1000);

// Settings: each control sends the stream's `settings` message; grading and encoding re-encode
// the image the server has, anything else restarts it.
for (const [id, name, convert] of [
  ['max-samples', 'max_samples', Number],
  ['tonemap', 'tonemap', String],
  ['encoding', 'encoding', String],
  ['quality', 'quality', Number],
]) {
  $(id).addEventListener('change', () => changeSettings({ [name]: convert($(id).value) }));
}
$('exposure').addEventListener('input', () => {
  $('exposure-value').textContent = $('exposure').value;
  changeSettings({ exposure: Number($('exposure').value) });
});
$('quality').addEventListener('input', () => ($('quality-value').textContent = $('quality').value));
$('integrator').addEventListener('change', () => {
  // The scene's own choice cannot be asked for on a stream that has one: it opens anew.
  if ($('integrator').value) changeSettings({ integrator: $('integrator').value });
  else if (sceneId !== null) openStream();
});
$('scale').addEventListener('change', sendSize);

/** How long the view must hold its size before the stream follows it, in ms (as the egui
 *  viewer's RESIZE_DEBOUNCE): a window being dragged larger does not restart the image at every
 *  step. */
const RESIZE_DEBOUNCE_MS = 300;
let resizeTimer = null;

function sendSize() {
  const [width, height] = wantedSize();
  if (sentSize && sentSize[0] === width && sentSize[1] === height) return;
  changeSettings({ width, height });
  sentSize = [width, height];
}

const followSize = () => {
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(sendSize, RESIZE_DEBOUNCE_MS);
};
new ResizeObserver(followSize).observe(view);
// A new device pixel ratio (browser zoom, another screen) changes no CSS size.
window.addEventListener('resize', followSize);

// ---------------------------------------------------------------------------------------------
// Camera changes: one in flight, the newest waiting (a fast drag never queues), as the egui
// viewer sends them. Each is an edit of the scene's camera, which every client of it sees.

/** How long a camera change waits for its reply before the next one goes anyway, in ms. */
const CAMERA_REPLY_TIMEOUT_MS = 2000;
const cameraQueue = { pending: null, since: null, inFlight: null };

/** The orbit changed at `time` (an input event's timeStamp, on performance.now()'s clock). */
function cameraMoved(time) {
  cameraQueue.pending = orbit.patch();
  cameraQueue.since ??= time;
  sendCamera();
}

function sendCamera() {
  const { pending, since, inFlight } = cameraQueue;
  if (!pending || (inFlight && performance.now() - inFlight.sent < CAMERA_REPLY_TIMEOUT_MS)) return;
  const request = send({ type: 'camera', camera: pending }, (reply) => {
    if (cameraQueue.inFlight?.request === request) cameraQueue.inFlight = null;
    if (latencyProbe?.request === request) {
      if (reply.type === 'result') latencyProbe.version = reply.version;
      else latencyProbe = null;
    }
    sendCamera();
  });
  if (request === null) return;
  cameraQueue.inFlight = { request, sent: performance.now() };
  cameraQueue.pending = cameraQueue.since = null;
  latencyProbe ??= { request, input: since, version: null };
  setTimeout(sendCamera, CAMERA_REPLY_TIMEOUT_MS);
}

// Latency from an input to the first frame showing it: from the earliest input a camera change
// carries to the drawing of the first frame of the scene version its reply names. One change
// is measured at a time.
let latencyProbe = null;
/** The last 50 measurements, in ms, and how many there have been (both kept on the statistics'
 *  element for scripts as well). */
const latencies = [];
let measured = 0;

function measureLatency(frame) {
  if (latencyProbe?.version == null || frame.scene_version < latencyProbe.version) return;
  latencies.push(performance.now() - latencyProbe.input);
  if (latencies.length > 50) latencies.shift();
  latencyProbe = null;
  $('stat-latency').dataset.count = ++measured;
  const sorted = [...latencies].sort((a, b) => a - b);
  const median = sorted[Math.floor(sorted.length / 2)];
  $('stat-latency').textContent = `${latencies.at(-1).toFixed(0)} ms (median ${median.toFixed(0)} of ${latencies.length})`;
  $('stat-latency').dataset.samples = JSON.stringify(latencies.map((ms) => Math.round(ms * 10) / 10));
}

// ---------------------------------------------------------------------------------------------
// Pointer, wheel, touch and keys. Left-drag orbits; right-, middle- or shift-drag pans; the
// wheel zooms; one finger orbits, two pan and pinch; a click (a press that moved less than
// CLICK_DISTANCE) picks.

/** Points a press may move and still be a click. */
const CLICK_DISTANCE = 4;
/** Points of scroll per wheel line (as egui counts a line). */
const POINTS_PER_LINE = 50;
/** Points of motion per arrow key press. */
const KEY_POINTS = 20;

/** Pointers down on the canvas: id → last position (client CSS pixels). */
const pointers = new Map();
/** The press in progress: where it started, which button, and whether it became a drag. */
let press = null;

canvas.addEventListener('pointerdown', (event) => {
  canvas.setPointerCapture(event.pointerId);
  canvas.focus();
  pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
  if (pointers.size === 1) {
    press = { x: event.clientX, y: event.clientY, pan: event.button === 1 || event.button === 2 || event.shiftKey, dragging: false, click: event.button === 0 };
  } else if (press) {
    // A second finger: a gesture, not a click.
    press.dragging = true;
  }
});

canvas.addEventListener('pointermove', (event) => {
  const last = pointers.get(event.pointerId);
  if (!last || !orbit || !press) return;
  if (pointers.size === 1) {
    // Until a press has moved CLICK_DISTANCE it may be a click: its position stays the press's,
    // so that a drag, once decided, moves by all of its motion.
    if (!press.dragging && Math.hypot(event.clientX - press.x, event.clientY - press.y) < CLICK_DISTANCE) return;
    press.dragging = true;
    const [dx, dy] = [event.clientX - last.x, event.clientY - last.y];
    pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    if (press.pan) orbit.pan(dx, dy, view.clientHeight);
    else orbit.orbit(dx, dy);
  } else if (pointers.size === 2) {
    const [a, b] = [...pointers.values()];
    const [midX, midY, spread] = [(a.x + b.x) / 2, (a.y + b.y) / 2, Math.hypot(a.x - b.x, a.y - b.y)];
    pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    const [c, d] = [...pointers.values()];
    orbit.pan((c.x + d.x) / 2 - midX, (c.y + d.y) / 2 - midY, view.clientHeight);
    // The eye's distance scales as the fingers' spread does, inversely.
    const newSpread = Math.hypot(c.x - d.x, c.y - d.y);
    if (spread > 0 && newSpread > 0) orbit.zoom(Math.log(newSpread / spread) / ZOOM_PER_POINT);
  } else {
    return;
  }
  cameraMoved(event.timeStamp);
});

function pointerGone(event) {
  if (!pointers.delete(event.pointerId)) return;
  if (pointers.size > 0) return;
  if (event.type === 'pointerup' && press && press.click && !press.dragging) pick(event.clientX, event.clientY);
  press = null;
}
canvas.addEventListener('pointerup', pointerGone);
canvas.addEventListener('pointercancel', pointerGone);
canvas.addEventListener('contextmenu', (event) => event.preventDefault());

canvas.addEventListener(
  'wheel',
  (event) => {
    event.preventDefault();
    if (!orbit) return;
    const points = [1, POINTS_PER_LINE, view.clientHeight][event.deltaMode] ?? 1;
    // The wheel turned away from the user (negative deltaY) brings the eye closer.
    orbit.zoom(-event.deltaY * points);
    cameraMoved(event.timeStamp);
  },
  { passive: false },
);

canvas.addEventListener('keydown', (event) => {
  if (!orbit) return;
  const arrows = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };
  if (event.key in arrows) {
    const [dx, dy] = arrows[event.key].map((k) => k * KEY_POINTS);
    if (event.shiftKey) orbit.pan(dx, dy, view.clientHeight);
    else orbit.orbit(dx, dy);
  } else if (event.key === '+' || event.key === '=') {
    orbit.zoom(5 * KEY_POINTS);
  } else if (event.key === '-') {
    orbit.zoom(-5 * KEY_POINTS);
  } else if (event.key === 'Enter' || event.key === ' ') {
    const rect = canvas.getBoundingClientRect();
    event.preventDefault();
    pick(rect.left + rect.width / 2, rect.top + rect.height / 2);
    return;
  } else {
    return;
  }
  event.preventDefault();
  cameraMoved(event.timeStamp);
});

// ---------------------------------------------------------------------------------------------
// Picking: what the clicked pixel of the image sees (`GET /scenes/{s}/pick`), highlighted with
// the instance-id channel (`GET /scenes/{s}/channels/instance`) of the image's size.

/** The selected instance and its object, or null. */
let selection = null;
/** The scene version the highlight shows, and whether one is being fetched. */
let highlighted = null;
let highlighting = false;
const highlightCanvas = $('highlight');

async function pick(clientX, clientY) {
  if (!shown) return;
  const rect = canvas.getBoundingClientRect();
  const x = clamp(Math.floor(((clientX - rect.left) / rect.width) * canvas.width), 0, canvas.width - 1);
  const y = clamp(Math.floor(((clientY - rect.top) / rect.height) * canvas.height), 0, canvas.height - 1);
  try {
    const { hit } = await getJson(`/scenes/${sceneId}/pick?x=${x}&y=${y}&width=${canvas.width}&height=${canvas.height}`);
    select(hit);
  } catch (error) {
    report(error);
  }
}

/** Selects `hit` (an instance and its object, and where a pick hit them), or nothing. */
function select(hit) {
  selection = hit;
  highlighted = null;
  const picked = $('picked');
  picked.classList.toggle('hit', Boolean(hit));
  picked.dataset.instance = hit ? hit.instance : '';
  if (!hit) {
    picked.textContent = 'Nothing selected: click the image to pick an instance.';
    highlightCanvas.getContext('2d').clearRect(0, 0, highlightCanvas.width, highlightCanvas.height);
    delete highlightCanvas.dataset.instance;
  } else {
    const where = hit.position ? ` (triangle ${hit.triangle}, ${hit.t.toFixed(3)} from the eye)` : '';
    picked.textContent = `instance ${hit.instance} of object ${hit.object}${where}`;
    highlight();
  }
  markSelected();
}

function markSelected() {
  for (const row of $('instances').tBodies[0].rows) row.classList.toggle('selected', selection !== null && row.dataset.id === String(selection.instance));
}

/** Draws the selected instance's outline over the image, fetching the ids of the scene version
 *  the image shows (again, once the image moves on while a fetch is in flight). */
async function highlight() {
  if (highlighting || !selection || !shown) return;
  highlighting = true;
  const [width, height, version, instance] = [canvas.width, canvas.height, shown.scene_version, selection.instance];
  try {
    const blob = await (await api(`/scenes/${sceneId}/channels/instance?width=${width}&height=${height}`)).blob();
    // Ids are bytes, not colours: no colour management may touch them.
    const bitmap = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const scratch = new OffscreenCanvas(width, height).getContext('2d');
    scratch.drawImage(bitmap, 0, 0);
    bitmap.close();
    if (selection?.instance === instance) drawHighlight(scratch.getImageData(0, 0, width, height), instance);
    highlighted = version;
  } catch (error) {
    report(error);
  } finally {
    highlighting = false;
  }
  if (selection && shown && highlighted !== shown.scene_version) highlight();
}

/** The pixels whose id (24 bits, red the low byte) is `instance`, tinted, with a solid edge. */
function drawHighlight(ids, instance) {
  const { width, height, data } = ids;
  const inside = (x, y) => {
    if (x < 0 || y < 0 || x >= width || y >= height) return false;
    const i = 4 * (y * width + x);
    return (data[i] | (data[i + 1] << 8) | (data[i + 2] << 16)) === instance;
  };
  const out = new ImageData(width, height);
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      if (!inside(x, y)) continue;
      const edge = !inside(x - 2, y) || !inside(x + 2, y) || !inside(x, y - 2) || !inside(x, y + 2);
      out.data.set([255, 176, 0, edge ? 255 : 70], 4 * (y * width + x));
    }
  }
  highlightCanvas.width = width;
  highlightCanvas.height = height;
  highlightCanvas.getContext('2d').putImageData(out, 0, 0);
  highlightCanvas.dataset.instance = instance;
}

// ---------------------------------------------------------------------------------------------
// The timeline of a scene with animations, on the scene's clock (`PUT /scenes/{s}/clock`), as
// crates/client/src/timeline.rs does it: the clock plays on the server, so every client sees the
// same moment and the page sends nothing while it plays, its slider following the time of the
// frames shown; a slider moved sends its time at most every SEND_INTERVAL_MS.

/** The least time between two times sent from the slider, in ms: each restarts the image, so
 *  sending faster would show fewer samples, not more poses. */
const SEND_INTERVAL_MS = 100;
const timeline = { animations: [], seconds: 0, playing: false, unsent: null, sentAt: -Infinity, timer: null };

/** Shows the timeline of `animations`, at the scene's `clock` if it has one (else at 0 s). */
function showTimeline(animations, clock) {
  timeline.animations = animations;
  timeline.unsent = null;
  $('timeline').hidden = animations.length === 0;
  $('animation-label').hidden = animations.length < 2;
  $('animation').replaceChildren(...animations.map((a, k) => new Option(a.name || `animation ${k}`, k)));
  followClock(clock ?? { animation: 0, time: 0, playing: false });
}

/** Takes the clock as the server has it. */
function followClock(clock) {
  const k = timeline.animations.findIndex((a) => a.index === clock.animation);
  if (k >= 0) $('animation').value = k;
  timeline.playing = clock.playing;
  if (timeline.unsent === null) timeline.seconds = clock.time;
  $('play').textContent = timeline.playing ? 'pause' : 'play';
  showTime();
}

/** While the clock plays, the slider shows the time of the frame on screen. */
function followFrame(message) {
  if (timeline.playing && timeline.unsent === null && typeof message.scene_time === 'number') {
    timeline.seconds = message.scene_time;
    showTime();
  }
}

const duration = () => Math.max(timeline.animations[Number($('animation').value)]?.duration ?? 0, 0);
const animationIndex = () => timeline.animations[Number($('animation').value)]?.index;

function showTime() {
  $('time').max = duration();
  $('time').value = timeline.seconds;
  $('time-value').textContent = timeline.seconds.toFixed(2);
}

/** Changes the scene's clock; shows the clock the server answers with. */
async function setClock(change) {
  try {
    const response = await api(`/scenes/${sceneId}/clock`, { method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(change) });
    followClock(await response.json());
  } catch (e) {
    if (!(e instanceof Unauthorized)) say(e.message);
  }
}

$('time').addEventListener('input', () => {
  timeline.seconds = Number($('time').value);
  timeline.unsent = timeline.seconds;
  showTime();
  sendTime();
});
$('animation').addEventListener('change', () => {
  timeline.seconds = 0;
  timeline.unsent = null;
  showTime();
  setClock({ animation: animationIndex(), time: 0 });
});
$('play').addEventListener('click', () => {
  timeline.playing = !timeline.playing;
  $('play').textContent = timeline.playing ? 'pause' : 'play';
  // Playing starts from the time on the slider; pausing keeps the clock's.
  const change = { playing: timeline.playing, animation: animationIndex() };
  if (timeline.playing) change.time = timeline.unsent ?? timeline.seconds;
  timeline.unsent = null;
  setClock(change);
});

/** Sends the time the slider was moved to, now or once SEND_INTERVAL_MS has passed since the
 *  last. */
function sendTime() {
  if (timeline.unsent === null) return;
  const wait = timeline.sentAt + SEND_INTERVAL_MS - performance.now();
  if (wait > 0) {
    clearTimeout(timeline.timer);
    timeline.timer = setTimeout(sendTime, wait);
    return;
  }
  const time = timeline.unsent;
  timeline.unsent = null;
  timeline.sentAt = performance.now();
  setClock({ time, animation: animationIndex() });
}

// ---------------------------------------------------------------------------------------------
// glTF files dropped on the page, or chosen with the button, become new scenes (`POST /scenes`
// with the file as the body), uploaded with progress.

const openFile = $('file');
$('open-file').addEventListener('click', () => openFile.click());
openFile.addEventListener('change', () => {
  if (openFile.files[0]) upload(openFile.files[0]);
  openFile.value = '';
});

const carriesFiles = (event) => event.dataTransfer?.types.includes('Files');
document.addEventListener('dragover', (event) => {
  if (!carriesFiles(event)) return;
  event.preventDefault();
  event.dataTransfer.dropEffect = 'copy';
  $('drop-hint').hidden = false;
});
document.addEventListener('dragleave', (event) => {
  // Leaving the window, not moving between the page's elements.
  if (event.relatedTarget === null) $('drop-hint').hidden = true;
});
document.addEventListener('drop', (event) => {
  if (!carriesFiles(event)) return;
  event.preventDefault();
  $('drop-hint').hidden = true;
  const file = event.dataTransfer.files[0];
  if (file) upload(file);
});

function upload(file) {
  const progress = $('upload-progress');
  const status = $('upload-status');
  const request = new XMLHttpRequest();
  request.open('POST', '/scenes');
  // A .gltf is JSON (its buffers as data: URIs); anything else is sent as binary glTF, which
  // the server checks.
  request.setRequestHeader('Content-Type', /\.gltf$/i.test(file.name) ? 'model/gltf+json' : 'model/gltf-binary');
  if (token) request.setRequestHeader('Authorization', `Bearer ${token}`);
  progress.hidden = false;
  progress.value = 0;
  status.textContent = `uploading ${file.name}…`;
  request.upload.addEventListener('progress', (event) => {
    if (!event.lengthComputable) return;
    progress.value = event.loaded / event.total;
    status.textContent = `uploading ${file.name}: ${Math.round((100 * event.loaded) / event.total)} %`;
  });
  request.upload.addEventListener('load', () => (status.textContent = `importing ${file.name}…`));
  request.addEventListener('load', async () => {
    progress.hidden = true;
    if (request.status === 401) {
      status.textContent = `${file.name} was not uploaded: the server needs a token`;
      askForToken();
      return;
    }
    if (request.status !== 201) {
      status.textContent = `${file.name} was refused: ${errorMessage(request.status, request.responseText)}`;
      return;
    }
    const scene = JSON.parse(request.responseText);
    status.textContent = `${file.name} is scene ${scene.id}`;
    status.dataset.scene = scene.id;
    try {
      listScenes(await getJson('/scenes'));
      await openScene(scene.id);
    } catch (error) {
      report(error);
    }
  });
  request.addEventListener('error', () => {
    progress.hidden = true;
    status.textContent = `${file.name} was not uploaded: the server could not be reached`;
  });
  request.send(file);
}

start();
