// The viewer page: connects to /ws (bridged to a node or troupe-sim), finds
// out which it is from the device list, draws the world and wires the
// controls. window.troupeViewer exposes the state for tests and the console.
import * as W from 'troupe-wire';
import { Connection, DeviceEntry } from './connection';
import { blobInWorld, draw, drawBlobs, View } from './draw';
import { CameraFrame, colorOf, Field, fmt, Pose, Robot, Scene } from './scene';

const kSimulation = 11, kMap = 10, kPosition2d = 1, kRanger = 2, kActuator = 7, kCamera = 13;
/// A press that moves less than this is a click, px.
const kClickSlop = 4;

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;
const canvas = $<HTMLCanvasElement>('world');
const view = new View(canvas);
const scene = new Scene();
const state = { selected: null as Robot | null, drag: null as { robot: Robot; pose: Pose } | null };
let mode: 'connecting' | 'sim' | 'node' = 'connecting';
let ready = false;
let closeReason = '';
let simDevice: DeviceEntry | undefined;
const opened = new Set<string>();

const conn = new Connection(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`, () => {
  start().catch((e) => setStatus(`error: ${e.message}`));
});
conn.onData = (msg, addr) => scene.onData(msg, addr);
conn.onClose = (why) => {
  closeReason = why;
  ready = false;
  document.body.dataset.ready = 'false';
  document.body.dataset.connected = 'false';
};
conn.onState = (link) => {
  document.body.dataset.link = link;
  showLink();
};

/// The status line while not connected: why, and when the next attempt is.
function showLink(): void {
  if (conn.state === 'open') return;
  const why = closeReason ? `disconnected: ${closeReason}; ` : '';
  if (conn.state === 'connecting') {
    setStatus(`${why}connecting${conn.failedAttempts ? ` (attempt ${conn.failedAttempts + 1})` : ''}…`);
  } else {
    const s = Math.max(0, (conn.retryAt - performance.now()) / 1000);
    setStatus(`${why}reconnecting in ${s.toFixed(1)} s (attempt ${conn.failedAttempts + 1})`);
  }
}

function setStatus(text: string): void {
  $('status').textContent = text;
}

/// Learns the world from a new connection: the first, or one after the
/// simulator or node restarted (then everything is learned again).
async function start(): Promise<void> {
  document.body.dataset.connected = 'true';
  closeReason = '';
  ready = false;
  mode = 'connecting';
  simDevice = undefined;
  opened.clear();
  state.selected = null;
  state.drag = null;
  scene.reset();
  document.body.classList.remove('node-mode');
  scene.devices = await conn.deviceList();
  simDevice = scene.devices.find((d) => d.addr.iface === kSimulation);
  if (simDevice) {
    mode = 'sim';
    const reply = await conn.request(simDevice.addr, W.SimulationReqSub.Models);
    const list = reply.body(new W.SimModelList()) as W.SimModelList;
    for (let i = 0; i < list.modelsLength(); ++i) {
      const m = list.models(i)!;
      addRobot({ name: m.name() || `robot ${i}`, number: m.robot(), pose: { x: 0, y: 0, a: 0 },
                 size: [m.sizeX(), m.sizeY()], color: colorOf(m.color()), trail: [],
                 disc: m.shape() === W.SimShape.Disc });
    }
    scene.field = fieldOf(list.field());
    await conn.open(simDevice.addr, W.Access.All);
    // A match: every kicker, so kicks show whichever robot is selected.
    for (const d of scene.devices) {
      if (scene.field && d.addr.iface === kActuator) await conn.open(d.addr, W.Access.Read).catch(() => {});
    }
    const clock = await conn.request(simDevice.addr, W.SimulationReqSub.GetClock);
    scene.onData(clock, simDevice.addr);
  } else {
    mode = 'node';
    scene.odometryPoses = true;
    document.body.classList.add('node-mode');
    for (const d of scene.devices) {
      if (d.addr.iface !== kPosition2d || scene.byNumber.has(d.addr.robot)) continue;
      addRobot({ name: d.robotName || conn.nodeName || `robot ${d.addr.robot}`, number: d.addr.robot,
                 pose: { x: 0, y: 0, a: 0 }, size: [0.45, 0.4], color: '#d04040', trail: [],
                 poseIndex: d.addr.index });
    }
    // A node's robot wanders off the first view: keep it in the middle.
    $<HTMLInputElement>('follow').checked = true;
    if (scene.robots.length) await select(scene.robots[0]);
  }
  const map = scene.devices.find((d) => d.addr.iface === kMap);
  if (map) {
    try {
      await scene.loadMap(conn, map.addr);
    } catch (e) {
      console.warn('map:', e);
    }
  }
  fitAll();
  buildRobotList();
  ready = true;
  document.body.dataset.ready = 'true';
}

function addRobot(r: Robot): void {
  scene.robots.push(r);
  scene.byNumber.set(r.number, r);
}

function fieldOf(f: W.SimField | null): Field | null {
  if (!f) return null;
  return { length: f.length(), width: f.width(), goalWidth: f.goalWidth(), goalDepth: f.goalDepth(),
           border: f.border(), centerCircle: f.centerCircleRadius(), penaltyDepth: f.penaltyDepth(),
           penaltyWidth: f.penaltyWidth(), cornerPostRadius: f.cornerPostRadius(),
           cornerPostOffset: f.cornerPostOffset() };
}

function fitAll(): void {
  if (scene.field) {
    const f = scene.field, x = f.length / 2 + f.border, y = f.width / 2 + f.border;
    view.fit(-x, -y, x, y);
  } else if (scene.map) {
    const m = scene.map;
    view.fit(m.origin.x, m.origin.y, m.origin.x + m.width * m.resolution, m.origin.y + m.height * m.resolution);
  } else if (scene.robots.length) {
    const xs = scene.robots.map((r) => r.pose.x), ys = scene.robots.map((r) => r.pose.y);
    view.fit(Math.min(...xs) - 3, Math.min(...ys) - 3, Math.max(...xs) + 3, Math.max(...ys) + 3);
  } else {
    view.fit(-5, -5, 5, 5);
  }
}

function buildRobotList(): void {
  const ul = $('robots');
  ul.replaceChildren();
  for (const r of scene.robots) {
    const li = document.createElement('li');
    li.dataset.robot = r.name;
    li.textContent = r.name;
    li.style.borderLeftColor = r.color;
    li.onclick = () => void select(r);
    ul.appendChild(li);
  }
}

/// Shows a robot's devices: opens them for reading, closes the previous
/// robot's (a simulated sensor is computed only while read).
async function select(r: Robot | null): Promise<void> {
  const previous = state.selected;
  state.selected = r;
  for (const li of $('robots').children) (li as HTMLElement).classList.toggle('selected', li.textContent === r?.name);
  if (mode === 'sim' && previous && previous !== r) {
    for (const d of devicesOf(previous)) {
      if (opened.delete(d.text)) await conn.closeDevice(d.addr).catch(() => {});
    }
  }
  if (!r) return;
  for (const d of devicesOf(r)) {
    if (opened.has(d.text)) continue;
    opened.add(d.text);
    if (d.addr.iface === kRanger) await scene.loadRanger(conn, d.addr);
    // Cameras send PNG: a tenth of the bytes through the bridge, decoded by the browser.
    const packing = d.addr.iface === kCamera ? W.ImageCompression.Png : W.ImageCompression.None;
    await conn.open(d.addr, W.Access.Read, packing)
      .catch((e) => scene.values.set(d.text, `cannot open: ${e.message}`));
  }
}

function devicesOf(r: Robot): DeviceEntry[] {
  return scene.devices.filter((d) => d.addr.robot === r.number && d.addr.iface !== kSimulation &&
                                     d.addr.iface !== kMap);
}

function robotAt(px: number, py: number): Robot | null {
  let best: Robot | null = null, bestD = Infinity;
  for (const r of scene.robots) {
    const [x, y] = view.toScreen(r.pose.x, r.pose.y);
    const reach = Math.max(r.size[0], r.size[1]) * view.scale / 2 + 6;
    const d = Math.hypot(px - x, py - y);
    if (d < reach && d < bestD) {
      best = r;
      bestD = d;
    }
  }
  return best;
}

// --- pointer: click selects, dragging a robot teleports it (sim), dragging
// the floor pans, the wheel zooms.
let press: { x: number; y: number; robot: Robot | null; moved: boolean; center: { x: number; y: number } } | null =
  null;
canvas.addEventListener('pointerdown', (ev) => {
  canvas.setPointerCapture(ev.pointerId);
  press = { x: ev.offsetX, y: ev.offsetY, robot: robotAt(ev.offsetX, ev.offsetY), moved: false,
            center: { ...view.center } };
});
canvas.addEventListener('pointermove', (ev) => {
  if (!press) return;
  if (Math.hypot(ev.offsetX - press.x, ev.offsetY - press.y) > kClickSlop) press.moved = true;
  if (!press.moved) return;
  if (press.robot && mode === 'sim') {
    const [x, y] = view.toWorld(ev.offsetX, ev.offsetY);
    state.drag = { robot: press.robot, pose: { x, y, a: press.robot.pose.a } };
  } else {
    view.center = { x: press.center.x - (ev.offsetX - press.x) / view.scale,
                    y: press.center.y + (ev.offsetY - press.y) / view.scale };
  }
});
canvas.addEventListener('pointerup', () => {
  const p = press;
  press = null;
  if (!p) return;
  if (state.drag && simDevice) {
    const { robot, pose } = state.drag;
    state.drag = null;
    void teleport(robot, pose);
  } else if (!p.moved) {
    void select(p.robot);
  }
});
canvas.addEventListener('wheel', (ev) => {
  ev.preventDefault();
  const [wx, wy] = view.toWorld(ev.offsetX, ev.offsetY);
  view.scale = Math.min(Math.max(view.scale * Math.exp(-ev.deltaY * 0.0015), 1), 2000);
  const [nx, ny] = view.toWorld(ev.offsetX, ev.offsetY);
  view.center = { x: view.center.x + wx - nx, y: view.center.y + wy - ny };
}, { passive: false });

async function teleport(r: Robot, pose: Pose): Promise<void> {
  try {
    await conn.request(simDevice!.addr, W.SimulationReqSub.SetPose, (b) => {
      const name = b.createString(r.name);
      W.SimPose.startSimPose(b);
      W.SimPose.addName(b, name);
      W.SimPose.addPose(b, W.Pose2d.createPose2d(b, pose.x, pose.y, pose.a));
      return [W.Body.SimPose, W.SimPose.endSimPose(b)];
    });
    // Shown at once; the next Poses message confirms it.
    r.pose = { ...pose };
    r.trail = [];
    teleports++;
  } catch (e) {
    notice = `teleport refused: ${(e as Error).message}`;
  }
}
let teleports = 0;
/// The last refusal, shown in the status line.
let notice = '';

// --- simulation controls
async function simRequest(sub: W.SimulationReqSub, body?: Parameters<Connection['request']>[2]): Promise<void> {
  if (!simDevice) return;
  let reply;
  try {
    reply = await conn.request(simDevice.addr, sub, body);
  } catch (e) {
    notice = `${W.SimulationReqSub[sub]} refused: ${(e as Error).message}`;
    return;
  }
  scene.onData(reply, simDevice.addr);  // the Ack carries the SimClock
  $('pause').textContent = scene.paused ? 'Resume' : 'Pause';
}
$('pause').onclick = () => void simRequest(scene.paused ? W.SimulationReqSub.Resume : W.SimulationReqSub.Pause);
$('step').onclick = () => void simRequest(W.SimulationReqSub.Step, (b) =>
  [W.Body.SimStep, W.SimStep.createSimStep(b, 1)]);
$<HTMLSelectElement>('speed').onchange = (ev) => {
  const speed = Number((ev.target as HTMLSelectElement).value);
  void simRequest(W.SimulationReqSub.SetSpeed, (b) => [W.Body.SimSpeed, W.SimSpeed.createSimSpeed(b, speed)]);
};
$('fit').onclick = () => fitAll();

// --- the panel and the frame loop
function updatePanel(): void {
  const r = state.selected;
  $('clock').textContent = mode === 'sim' ?
    `t = ${scene.simTime.toFixed(1)} s${scene.paused ? ' (paused)' : ''}, ×${fmt(scene.realTimeFactor)}` : '';
  $('pause').textContent = scene.paused ? 'Resume' : 'Pause';
  // Show the simulator's speed (another client, or --speed, may set it).
  const speed = $<HTMLSelectElement>('speed');
  const option = [...speed.options].find((o) => Number(o.value) === scene.speed);
  if (document.activeElement !== speed && option) speed.value = option.value;
  document.body.dataset.paused = String(scene.paused);
  if (ready && conn.state === 'open') {
    const what = mode === 'sim' ? `troupe-sim, ${scene.robots.length} robots` :
                                  `node ${conn.nodeName || ''}, ${scene.devices.length} devices`;
    setStatus(`connected: ${what}${conn.opens > 1 ? ` (reconnected ${conn.opens - 1}×)` : ''}` +
              `${notice ? '; ' + notice : ''}`);
  } else {
    showLink();
  }
  const panel = $('selected');
  if (!r) {
    panel.replaceChildren();
    return;
  }
  const title = document.createElement('h2');
  title.textContent = r.name;
  const pose = document.createElement('p');
  pose.textContent = `${mode === 'sim' ? 'true pose' : 'odometry'}: ${fmt(r.pose.x)}, ${fmt(r.pose.y)} m, ` +
                     `${fmt(r.pose.a)} rad`;
  const ul = document.createElement('ul');
  ul.id = 'devices';
  for (const d of devicesOf(r)) {
    const li = document.createElement('li');
    li.dataset.device = d.text;
    const name = document.createElement('b');
    name.textContent = d.text;
    const value = document.createElement('span');
    value.textContent = scene.values.get(`${d.addr.robot}/${d.addr.iface}:${d.addr.index}`) ?? '(no data yet)';
    li.append(name, document.createElement('br'), value);
    const blobs = scene.blobs.get(`${d.addr.robot}/${d.addr.iface}:${d.addr.index}`);
    if (blobs) {
      const c = document.createElement('canvas');
      c.width = 160;
      c.height = 120;
      drawBlobs(c, blobs);
      li.append(document.createElement('br'), c);
    }
    const camera = scene.cameras.get(`${d.addr.robot}/${d.addr.iface}:${d.addr.index}`);
    if (camera) li.append(document.createElement('br'), cameraCanvas(camera));
    ul.appendChild(li);
  }
  panel.replaceChildren(title, pose, ul);
}

/// The camera's image at its own size, one canvas pixel per image pixel
/// (CSS may scale it; the canvas keeps the values).
function cameraCanvas(frame: CameraFrame): HTMLCanvasElement {
  const c = document.createElement('canvas');
  c.className = 'camera';
  c.width = frame.width;
  c.height = frame.height;
  const g = c.getContext('2d')!;
  if (frame.image instanceof ImageData) g.putImageData(frame.image, 0, 0);
  else g.drawImage(frame.image, 0, 0);
  return c;
}

let lastPanel = 0;
function frame(t: number): void {
  if ($<HTMLInputElement>('follow').checked && state.selected) {
    view.center = { x: state.selected.pose.x, y: state.selected.pose.y };
  }
  draw(view, scene, state);
  if (t - lastPanel > 200) {
    lastPanel = t;
    updatePanel();
  }
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);

// For tests and the console: state in wire units (m, rad, s), positions on
// the page in CSS pixels.
(window as any).troupeViewer = {
  get ready() { return ready; },
  get mode() { return mode; },
  get closeReason() { return closeReason; },
  get link() { return conn.state; },
  get opens() { return conn.opens; },
  get simTime() { return scene.simTime; },
  get steps() { return scene.steps; },
  get paused() { return scene.paused; },
  get framesIn() { return conn.framesIn; },
  get pendingRequests() { return conn.pendingCount; },
  get teleports() { return teleports; },
  get selected() { return state.selected?.name ?? null; },
  robots: () => scene.robots.map((r) => r.name),
  field: () => scene.field,
  game: () => scene.game,
  kicking: () => scene.robots.filter((r) => scene.kicks.has(r.number)).map((r) => r.name),
  /// The canvas colour at a world point, '#rrggbb'.
  colorAt: (x: number, y: number) => {
    const [sx, sy] = view.toScreen(x, y);
    const dpr = window.devicePixelRatio || 1;
    const d = canvas.getContext('2d')!.getImageData(Math.round(sx * dpr), Math.round(sy * dpr), 1, 1).data;
    return '#' + [d[0], d[1], d[2]].map((v) => v.toString(16).padStart(2, '0')).join('');
  },
  devices: () => scene.devices.map((d) => d.text),
  pose: (name: string) => { const r = scene.robot(name); return r ? { ...r.pose } : null; },
  trailLength: (name: string) => scene.robot(name)?.trail.length ?? 0,
  values: () => Object.fromEntries(scene.devices.map((d) =>
    [d.text, scene.values.get(`${d.addr.robot}/${d.addr.iface}:${d.addr.index}`) ?? null])),
  beams: () => [...scene.rangers.values()].reduce((n, v) => n + v.ranges.length, 0),
  /// The selected robot's blobs as drawn in the world view: colour, world
  /// position (m) and page position (CSS px) of each.
  worldBlobs: () => {
    const r = state.selected;
    if (!r) return [];
    const box = canvas.getBoundingClientRect();
    return [...scene.blobs].filter(([key]) => key.startsWith(`${r.number}/`)).flatMap(([, image]) =>
      image.list.map((b) => {
        const { at, width } = blobInWorld(r.pose, image, b);
        const [x, y] = view.toScreen(at.x, at.y);
        return { color: colorOf(b.color), x: at.x, y: at.y, width, pageX: box.left + x, pageY: box.top + y };
      }));
  },
  screenOf: (name: string) => {
    const r = scene.robot(name);
    if (!r) return null;
    const [x, y] = view.toScreen(r.pose.x, r.pose.y);
    const box = canvas.getBoundingClientRect();
    return { x: box.left + x, y: box.top + y };
  },
  worldAt: (clientX: number, clientY: number) => {
    const box = canvas.getBoundingClientRect();
    const [x, y] = view.toWorld(clientX - box.left, clientY - box.top);
    return { x, y };
  },
  select: (name: string) => select(scene.robot(name) ?? null),
  sendRaw: (bytes: number[]) => conn.sendRaw(new Uint8Array(bytes)),
};
