// Drawing the scene on a 2D canvas. The view maps world metres to CSS
// pixels: x right, y up, `scale` pixels per metre around `center`.
import { BlobImage, BlobView, colorOf, compose, Field, Game, Pose, Robot, Scene } from './scene';

/// A blobfinder's horizontal field of view, rad. The wire's blob list does
/// not carry it; this is troupe-sim's and Stage's default (60 degrees).
const kBlobFov = Math.PI / 3;
/// How far a blob of unknown range is drawn (as a bearing ray), m.
const kBlobRayM = 3;

export class View {
  center = { x: 0, y: 0 }; // m
  scale = 40; // px per m

  constructor(public canvas: HTMLCanvasElement) {}

  /// World (m) to canvas pixels.
  toScreen(x: number, y: number): [number, number] {
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    return [w / 2 + (x - this.center.x) * this.scale, h / 2 - (y - this.center.y) * this.scale];
  }

  /// Canvas pixels to world (m).
  toWorld(px: number, py: number): [number, number] {
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    return [this.center.x + (px - w / 2) / this.scale, this.center.y - (py - h / 2) / this.scale];
  }

  /// Frames a box (m) with a margin.
  fit(x0: number, y0: number, x1: number, y1: number): void {
    const w = Math.max(this.canvas.clientWidth, 1), h = Math.max(this.canvas.clientHeight, 1);
    this.center = { x: (x0 + x1) / 2, y: (y0 + y1) / 2 };
    this.scale = 0.92 * Math.min(w / Math.max(x1 - x0, 0.1), h / Math.max(y1 - y0, 0.1));
  }
}

export interface DrawState {
  selected: Robot | null;
  /// A robot being dragged and where it would go.
  drag: { robot: Robot; pose: Pose } | null;
}

export function draw(view: View, scene: Scene, state: DrawState): void {
  const canvas = view.canvas;
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
  }
  const ctx = canvas.getContext('2d')!;
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.fillStyle = '#f4f4f0';
  ctx.fillRect(0, 0, w, h);
  drawGrid(ctx, view, w, h);

  if (scene.map) {
    const m = scene.map;
    const [sx, sy] = view.toScreen(m.origin.x, m.origin.y + m.height * m.resolution);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(m.canvas, sx, sy, m.width * m.resolution * view.scale, m.height * m.resolution * view.scale);
  }

  if (scene.field) drawField(ctx, view, scene.field);
  for (const r of scene.robots) drawTrail(ctx, view, r, r === state.selected);
  if (state.selected) {
    drawSensors(ctx, view, scene, state.selected);
    drawWorldBlobs(ctx, view, scene, state.selected);
  }
  for (const r of scene.robots) {
    const dragged = state.drag?.robot === r;
    if (scene.kicks.has(r.number)) drawKick(ctx, view, r);
    drawRobot(ctx, view, r, r.pose, r === state.selected, dragged ? 0.35 : 1);
    if (dragged) drawRobot(ctx, view, r, state.drag!.pose, true, 1);
  }
  if (scene.game) drawScore(ctx, w, scene.game);
}

/// The pitch: grass to the barrier, white lines, the centre circle, the
/// penalty areas, the goals (blue at -x, yellow at +x) and the corner posts.
function drawField(ctx: CanvasRenderingContext2D, view: View, f: Field): void {
  const L = f.length / 2, H = f.width / 2, B = f.border;
  const rect = (x0: number, y0: number, x1: number, y1: number) => {
    const [sx0, sy0] = view.toScreen(x0, y1);
    const [sx1, sy1] = view.toScreen(x1, y0);
    return [sx0, sy0, sx1 - sx0, sy1 - sy0] as const;
  };
  ctx.fillStyle = '#3f8f3f';
  ctx.fillRect(...rect(-L - B, -H - B, L + B, H + B));
  ctx.strokeStyle = '#ffffff';
  ctx.lineWidth = Math.max(1, 0.05 * view.scale);
  ctx.strokeRect(...rect(-L, -H, L, H));
  const [cx, cy] = view.toScreen(0, 0);
  const [, top] = view.toScreen(0, H), [, bottom] = view.toScreen(0, -H);
  ctx.beginPath();
  ctx.moveTo(cx, top);
  ctx.lineTo(cx, bottom);
  ctx.moveTo(cx + f.centerCircle * view.scale, cy);
  ctx.arc(cx, cy, f.centerCircle * view.scale, 0, 2 * Math.PI);
  ctx.stroke();
  const P = f.penaltyWidth / 2, G = f.goalWidth / 2;
  for (const side of [-1, 1]) {
    const x0 = side * L, x1 = side * (L - f.penaltyDepth);
    ctx.strokeRect(...rect(Math.min(x0, x1), -P, Math.max(x0, x1), P));
    const g0 = side * L, g1 = side * (L + f.goalDepth);
    ctx.fillStyle = side < 0 ? '#1e50ff' : '#ffd21e';
    ctx.fillRect(...rect(Math.min(g0, g1), -G, Math.max(g0, g1), G));
    for (const yside of [-1, 1]) {
      const [px, py] = view.toScreen(side * (L + f.cornerPostOffset), yside * (H + f.cornerPostOffset));
      ctx.fillStyle = '#e0e0e0';
      ctx.beginPath();
      ctx.arc(px, py, Math.max(f.cornerPostRadius * view.scale, 2), 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}

/// A kick: a burst in front of the robot while its kicker is out.
function drawKick(ctx: CanvasRenderingContext2D, view: View, r: Robot): void {
  const front = compose(r.pose, { x: r.size[0] / 2 + 0.1, y: 0, a: 0 });
  const [x, y] = view.toScreen(front.x, front.y);
  ctx.strokeStyle = '#ff3020';
  ctx.lineWidth = 3;
  ctx.beginPath();
  ctx.arc(x, y, Math.max(0.15 * view.scale, 6), 0, 2 * Math.PI);
  ctx.stroke();
}

/// The score, top centre: blue first (it defends -x, drawn on the left).
function drawScore(ctx: CanvasRenderingContext2D, w: number, g: Game): void {
  const text = `blue ${g.blue} : ${g.yellow} yellow` + (g.lastEvent ? `  (${g.lastEvent})` : '');
  ctx.font = 'bold 16px sans-serif';
  ctx.textAlign = 'center';
  const width = ctx.measureText(text).width + 16;
  ctx.fillStyle = 'rgba(255, 255, 255, 0.85)';
  ctx.fillRect(w / 2 - width / 2, 6, width, 24);
  ctx.fillStyle = '#111';
  ctx.fillText(text, w / 2, 24);
}

function drawGrid(ctx: CanvasRenderingContext2D, view: View, w: number, h: number): void {
  // One line a metre (or every 10 m when zoomed far out).
  const step = view.scale < 8 ? 10 : 1;
  const [x0, y1] = view.toWorld(0, 0);
  const [x1, y0] = view.toWorld(w, h);
  ctx.strokeStyle = '#e2e2dc';
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
    const [sx] = view.toScreen(x, 0);
    ctx.moveTo(sx, 0);
    ctx.lineTo(sx, h);
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
    const [, sy] = view.toScreen(0, y);
    ctx.moveTo(0, sy);
    ctx.lineTo(w, sy);
  }
  ctx.stroke();
}

function drawTrail(ctx: CanvasRenderingContext2D, view: View, r: Robot, selected: boolean): void {
  if (r.trail.length < 2) return;
  ctx.strokeStyle = selected ? 'rgba(30, 90, 200, 0.9)' : 'rgba(90, 70, 40, 0.4)';
  ctx.lineWidth = selected ? 2 : 1;
  ctx.beginPath();
  r.trail.forEach((p, i) => {
    const [x, y] = view.toScreen(p.x, p.y);
    if (i === 0) ctx.moveTo(x, y);
    else ctx.lineTo(x, y);
  });
  const [x, y] = view.toScreen(r.pose.x, r.pose.y);
  ctx.lineTo(x, y);
  ctx.stroke();
}

function drawRobot(ctx: CanvasRenderingContext2D, view: View, r: Robot, pose: Pose, selected: boolean,
                   alpha: number): void {
  const [x, y] = view.toScreen(pose.x, pose.y);
  const sw = Math.max(r.size[0] * view.scale, 6), sh = Math.max(r.size[1] * view.scale, 6);
  ctx.save();
  ctx.globalAlpha = alpha;
  ctx.translate(x, y);
  ctx.rotate(-pose.a);
  ctx.fillStyle = r.color;
  ctx.strokeStyle = selected ? '#1e5ac8' : '#222';
  ctx.lineWidth = selected ? 3 : 1;
  if (r.disc) {
    ctx.beginPath();
    ctx.arc(0, 0, sw / 2, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
  } else {
    ctx.fillRect(-sw / 2, -sh / 2, sw, sh);
    ctx.strokeRect(-sw / 2, -sh / 2, sw, sh);
    ctx.beginPath();
    ctx.moveTo(0, 0);
    ctx.lineTo(sw / 2, 0);
    ctx.stroke();
  }
  ctx.restore();
  ctx.globalAlpha = alpha;
  ctx.fillStyle = '#111';
  ctx.font = '11px sans-serif';
  ctx.textAlign = 'center';
  ctx.fillText(r.name, x, y - sh / 2 - 4);
  ctx.globalAlpha = 1;
}

function drawSensors(ctx: CanvasRenderingContext2D, view: View, scene: Scene, r: Robot): void {
  for (const [key, ranger] of scene.rangers) {
    if (!key.startsWith(`${r.number}/`)) continue;
    const mount = compose(r.pose, ranger.mount);
    ctx.strokeStyle = 'rgba(0, 160, 60, 0.55)';
    ctx.fillStyle = 'rgba(0, 130, 50, 0.9)';
    ctx.lineWidth = 1;
    ranger.ranges.forEach((range, i) => {
      let from: Pose;
      if (ranger.resolution !== 0 || ranger.elements.length <= i) {
        from = { ...mount, a: mount.a + ranger.minAngle + i * ranger.resolution };
      } else {
        from = compose(r.pose, ranger.elements[i]);
      }
      const end = compose(from, { x: range, y: 0, a: 0 });
      const [x0, y0] = view.toScreen(from.x, from.y);
      const [x1, y1] = view.toScreen(end.x, end.y);
      ctx.beginPath();
      ctx.moveTo(x0, y0);
      ctx.lineTo(x1, y1);
      ctx.stroke();
      if (range < ranger.maxRange * 0.999) ctx.fillRect(x1 - 1.5, y1 - 1.5, 3, 3);
    });
  }
  for (const [key, list] of scene.fiducials) {
    if (!key.startsWith(`${r.number}/`)) continue;
    for (const f of list) {
      const p = compose(r.pose, { x: f.x, y: f.y, a: 0 });
      const [x, y] = view.toScreen(p.x, p.y);
      ctx.strokeStyle = '#c05000';
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.arc(x, y, 7, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.fillStyle = '#c05000';
      ctx.font = 'bold 10px sans-serif';
      ctx.fillText(`#${f.id}`, x + 14, y + 3);
    }
  }
}

/// Where a blob is in the world, seen by `robot` (the blobfinder at its
/// centre, looking ahead): its bearing from the image column (x grows to
/// the right, against the bearing), its range from the data. The blob's
/// width across the view, m (0 when its range is unknown).
export function blobInWorld(robot: Pose, image: BlobImage, blob: BlobView): { at: Pose; width: number } {
  const w = Math.max(image.width, 1);
  const bearing = (0.5 - (blob.x + 0.5) / w) * kBlobFov;
  const range = blob.range > 0 ? blob.range : kBlobRayM;
  const at = compose(robot, { x: range * Math.cos(bearing), y: range * Math.sin(bearing), a: bearing });
  const width = blob.range > 0 ? ((blob.r - blob.l + 1) / w) * kBlobFov * blob.range : 0;
  return { at, width };
}

/// The selected robot's blobs in the world view: a disc of the blob's
/// colour where it was seen (a dashed ray where its range is unknown),
/// joined to the robot.
function drawWorldBlobs(ctx: CanvasRenderingContext2D, view: View, scene: Scene, r: Robot): void {
  for (const [key, image] of scene.blobs) {
    if (!key.startsWith(`${r.number}/`)) continue;
    const [rx, ry] = view.toScreen(r.pose.x, r.pose.y);
    for (const blob of image.list) {
      const { at, width } = blobInWorld(r.pose, image, blob);
      const [x, y] = view.toScreen(at.x, at.y);
      ctx.strokeStyle = colorOf(blob.color);
      ctx.lineWidth = 1.5;
      ctx.setLineDash(width > 0 ? [] : [4, 4]);
      ctx.beginPath();
      ctx.moveTo(rx, ry);
      ctx.lineTo(x, y);
      ctx.stroke();
      ctx.setLineDash([]);
      if (width <= 0) continue;
      ctx.fillStyle = colorOf(blob.color);
      ctx.strokeStyle = '#111';
      ctx.beginPath();
      ctx.arc(x, y, Math.max((width / 2) * view.scale, 5), 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    }
  }
}

/// The blobs of a blobfinder as its camera image sees them.
export function drawBlobs(canvas: HTMLCanvasElement, blobs: BlobImage): void {
  const ctx = canvas.getContext('2d')!;
  ctx.fillStyle = '#222';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const sx = canvas.width / Math.max(blobs.width, 1), sy = canvas.height / Math.max(blobs.height, 1);
  for (const b of blobs.list) {
    ctx.fillStyle = colorOf(b.color);
    ctx.fillRect(b.l * sx, b.t * sy, Math.max((b.r - b.l + 1) * sx, 2), Math.max((b.b - b.t + 1) * sy, 2));
  }
}
