// What the page knows about the world: robots (ground truth from
// simulation:0, or odometry from a node's position2d), their trails, the
// map, and the latest data of each device it reads. Units are the wire's:
// m, rad; times in s.
import * as W from 'troupe-wire';
import { Address, addrKey, Connection, DeviceEntry } from './connection';

export interface Pose {
  x: number; // m
  y: number; // m
  a: number; // rad
}

export interface Robot {
  name: string;
  /// wire robot number of its devices
  number: number;
  pose: Pose;
  size: [number, number]; // m
  color: string;
  trail: Pose[];
  /// On a node: the position2d index whose odometry places the robot (a
  /// node may serve several estimates of one robot).
  poseIndex?: number;
  /// Drawn as a disc of diameter size[0] (a ball, a puck), not a box.
  disc?: boolean;
}

/// A RoboCup field (simulation:0's SimField), m; goals on the x axis.
export interface Field {
  length: number;
  width: number;
  goalWidth: number;
  goalDepth: number;
  border: number;
  centerCircle: number;
  penaltyDepth: number;
  penaltyWidth: number;
  cornerPostRadius: number;
  cornerPostOffset: number;
}

/// A match's state (simulation:0's SimGame).
export interface Game {
  blue: number;
  yellow: number;
  phase: W.GamePhase;
  lastEvent: string;
}

/// A ranger's mounting (robot frame) and its latest scan's beam ends.
export interface RangerView {
  mount: Pose; // robot frame, m, rad
  elements: Pose[]; // per transducer (sonar rings), robot frame
  ranges: number[]; // m
  minAngle: number; // rad, relative to the mount
  resolution: number; // rad between beams; 0: one beam per element
  maxRange: number; // m
}

/// One blob of a blobfinder: image pixels (x right, y down) and range.
export interface BlobView {
  color: number; // 0x00RRGGBB
  x: number; // centroid, px
  y: number;
  l: number; // bounding box, px
  r: number;
  t: number;
  b: number;
  range: number; // m; 0: unknown
}

/// A blobfinder's latest image: its size and blobs.
export interface BlobImage {
  width: number; // px
  height: number; // px
  list: BlobView[];
}

/// A camera's latest image, ready to draw at its size: decoded by the
/// browser from PNG, or built from raw Rgb8/Mono8 rows.
export interface CameraFrame {
  width: number; // px
  height: number; // px
  image: ImageBitmap | ImageData;
}

export interface MapImage {
  width: number; // cells
  height: number; // cells
  resolution: number; // m per cell
  origin: Pose; // corner of cell (0, 0), m
  canvas: HTMLCanvasElement;
}

/// A trail keeps this many poses, the newest last.
const kTrailPoses = 300;
/// A new trail point only after this much motion, m.
const kTrailStep = 0.02;
/// Largest map tile asked for, cells a side (the map interface's limit).
const kTile = 512;

/** A detection as the panel lists it: its kind, unless generic, and its id. */
export function fiducialLabel(kind: W.FiducialKind, id: number): string {
  return kind === W.FiducialKind.Generic ? `#${id}` : `${W.FiducialKind[kind].toLowerCase()} ${id}`;
}

export function colorOf(rgb: number): string {
  return '#' + (rgb & 0xffffff).toString(16).padStart(6, '0');
}

export function compose(a: Pose, b: Pose): Pose {
  const c = Math.cos(a.a), s = Math.sin(a.a);
  return { x: a.x + c * b.x - s * b.y, y: a.y + s * b.x + c * b.y, a: a.a + b.a };
}

export function pushTrail(r: Robot): void {
  const last = r.trail[r.trail.length - 1];
  if (last && Math.hypot(last.x - r.pose.x, last.y - r.pose.y) < kTrailStep) return;
  r.trail.push({ ...r.pose });
  if (r.trail.length > kTrailPoses) r.trail.splice(0, r.trail.length - kTrailPoses);
}

export class Scene {
  robots: Robot[] = [];
  byNumber = new Map<number, Robot>();
  devices: DeviceEntry[] = [];
  map: MapImage | null = null;
  /// Latest value of each device read, by addrKey, as text for the panel.
  values = new Map<string, string>();
  rangers = new Map<string, RangerView>();
  blobs = new Map<string, BlobImage>();
  cameras = new Map<string, CameraFrame>();
  /// Images received per camera: a PNG decoded late does not replace a newer image.
  private cameraImages = new Map<string, number>();
  fiducials = new Map<string, { id: number; x: number; y: number; a: number; kind: W.FiducialKind }[]>();
  field: Field | null = null;
  game: Game | null = null;
  /// Robot numbers whose kicker (actuator) is out, and when it fired, s.
  kicks = new Map<number, number>();
  simTime = 0; // s
  steps = 0;
  paused = false;
  speed = 1;
  realTimeFactor = 0;

  /// Forgets everything learned from the previous connection: a restarted
  /// simulator or node may serve another world.
  reset(): void {
    this.robots = [];
    this.byNumber.clear();
    this.devices = [];
    this.map = null;
    this.values.clear();
    this.rangers.clear();
    this.blobs.clear();
    this.cameras.clear();
    this.fiducials.clear();
    this.simTime = 0;
    this.steps = 0;
    this.paused = false;
    this.odometryPoses = false;
  }

  robot(name: string): Robot | undefined {
    return this.robots.find((r) => r.name === name);
  }

  /// Fetches the map of a map device as one image (tile by tile).
  async loadMap(c: Connection, addr: Address): Promise<void> {
    const infoMsg = await c.request(addr, W.MapReqSub.Info);
    const info = infoMsg.body(new W.MapInfo()) as W.MapInfo;
    const w = info.width(), h = info.height();
    if (w === 0 || h === 0) return;
    const o = info.origin();
    const canvas = document.createElement('canvas');
    canvas.width = w;
    canvas.height = h;
    const ctx = canvas.getContext('2d')!;
    const image = ctx.createImageData(w, h);
    for (let row = 0; row < h; row += kTile) {
      for (let col = 0; col < w; col += kTile) {
        const tw = Math.min(kTile, w - col), th = Math.min(kTile, h - row);
        const msg = await c.request(addr, W.MapReqSub.Tile, (b) =>
          [W.Body.MapTileRequest, W.MapTileRequest.createMapTileRequest(b, col, row, tw, th)]);
        const tile = msg.body(new W.MapTile()) as W.MapTile;
        const cells = tile.cellsArray() || new Uint8Array(0);
        for (let i = 0; i < tw * th; ++i) {
          const v = ((cells[i >> 2] ?? 0) >> (2 * (i & 3))) & 3;
          const x = col + (i % tw), y = row + Math.floor(i / tw);
          // Row 0 is the bottom of the map (y up); images go down.
          const p = ((h - 1 - y) * w + x) * 4;
          const shade = v === W.Cell.Occupied ? 40 : v === W.Cell.Unknown ? 200 : 255;
          image.data[p] = image.data[p + 1] = image.data[p + 2] = shade;
          image.data[p + 3] = v === W.Cell.Free ? 0 : 255;
        }
      }
    }
    ctx.putImageData(image, 0, 0);
    this.map = { width: w, height: h, resolution: info.resolution(),
                 origin: { x: o ? o.x() : 0, y: o ? o.y() : 0, a: o ? o.a() : 0 }, canvas };
  }

  /// Reads a ranger's mounting; a device that does not say is at the
  /// robot's centre.
  async loadRanger(c: Connection, addr: Address): Promise<void> {
    const view: RangerView = { mount: { x: 0, y: 0, a: 0 }, elements: [], ranges: [], minAngle: 0, resolution: 0,
                               maxRange: 0 };
    try {
      const msg = await c.request(addr, W.RangerReqSub.Geometry);
      const g = msg.body(new W.RangerGeometry()) as W.RangerGeometry;
      const p = g.pose();
      if (p) view.mount = { x: p.x(), y: p.y(), a: p.yaw() };
      for (let i = 0; i < g.elementsLength(); ++i) {
        const e = g.elements(i)!;
        view.elements.push({ x: e.x(), y: e.y(), a: e.yaw() });
      }
    } catch (e) {
      // No geometry (e.g. a logged laser): beams from the robot's centre.
    }
    this.rangers.set(addrKey(addr), view);
  }

  /// Applies one Data frame.
  onData(msg: W.Message, addr: Address): void {
    const key = addrKey(addr);
    switch (msg.bodyType()) {
      case W.Body.SimClock: {
        const s = msg.body(new W.SimClock()) as W.SimClock;
        this.simTime = Number(s.simTimeUs()) / 1e6;
        this.steps = Number(s.steps());
        this.paused = s.paused();
        this.speed = s.speed();
        this.realTimeFactor = s.realTimeFactor();
        return;
      }
      case W.Body.SimPoses: {
        const s = msg.body(new W.SimPoses()) as W.SimPoses;
        const n = Math.min(s.posesLength(), this.robots.length);
        for (let i = 0; i < n; ++i) {
          const p = s.poses(i)!;
          const r = this.robots[i];
          r.pose = { x: p.x(), y: p.y(), a: p.a() };
          pushTrail(r);
        }
        return;
      }
      case W.Body.Position2dState: {
        const s = msg.body(new W.Position2dState()) as W.Position2dState;
        const p = s.pose(), v = s.vel();
        this.values.set(key, `odometry ${fmt(p?.x())}, ${fmt(p?.y())} m, ${fmt(p?.a())} rad; ` +
                             `velocity ${fmt(v?.x())} m/s, ${fmt(v?.a())} rad/s${s.stall() ? '; STALLED' : ''}`);
        const r = this.byNumber.get(addr.robot);
        // A node's robot is drawn where its odometry says.
        if (r && p && this.odometryPoses && addr.index === r.poseIndex) {
          r.pose = { x: p.x(), y: p.y(), a: p.a() };
          pushTrail(r);
        }
        return;
      }
      case W.Body.RangerScan: {
        const s = msg.body(new W.RangerScan()) as W.RangerScan;
        const raw = s.rangesArray() || new Uint16Array(0);
        const scale = s.scale();
        const view = this.rangers.get(key);
        const ranges = Array.from(raw, (v) => v * scale);
        if (view) {
          view.ranges = ranges;
          view.minAngle = s.minAngle();
          view.resolution = s.angularRes();
          view.maxRange = s.maxRange();
        }
        const near = ranges.length ? Math.min(...ranges) : NaN;
        this.values.set(key, `${ranges.length} ranges, nearest ${fmt(near)} m, max ${fmt(s.maxRange())} m`);
        return;
      }
      case W.Body.BlobList: {
        const s = msg.body(new W.BlobList()) as W.BlobList;
        const list: BlobView[] = [];
        for (let i = 0; i < s.blobsLength(); ++i) {
          const b = s.blobs(i)!;
          list.push({ color: b.color(), x: b.x(), y: b.y(), l: b.left(), r: b.right(), t: b.top(), b: b.bottom(),
                      range: b.rangeMm() / 1000 });
        }
        this.blobs.set(key, { width: s.width(), height: s.height(), list });
        this.values.set(key, `${list.length} blobs` + list.map((b) => ` ${colorOf(b.color)}@${b.x},${b.y}`).join(''));
        return;
      }
      case W.Body.FiducialList: {
        const s = msg.body(new W.FiducialList()) as W.FiducialList;
        const list = [];
        for (let i = 0; i < s.fiducialsLength(); ++i) {
          const f = s.fiducials(i)!;
          const kind = i < s.kindsLength() ? s.kinds(i)! : W.FiducialKind.Generic;
          list.push({ id: f.id(), x: f.x(), y: f.y(), a: f.yaw(), kind });
        }
        this.fiducials.set(key, list);
        this.values.set(key, `${list.length} fiducials` + list.map((f) => ` ${fiducialLabel(f.kind, f.id)}`).join(''));
        return;
      }
      case W.Body.SimGame: {
        const s = msg.body(new W.SimGame()) as W.SimGame;
        this.game = { blue: s.scoreBlue(), yellow: s.scoreYellow(), phase: s.phase(), lastEvent: s.lastEvent() || '' };
        return;
      }
      case W.Body.ActuatorState: {
        const s = msg.body(new W.ActuatorState()) as W.ActuatorState;
        if (s.mode() === W.ActuatorMode.Kicking) {
          if (!this.kicks.has(addr.robot)) this.kicks.set(addr.robot, this.simTime);
        } else {
          this.kicks.delete(addr.robot);
        }
        this.values.set(key, W.ActuatorMode[s.mode()]);
        return;
      }
      case W.Body.PowerState: {
        const s = msg.body(new W.PowerState()) as W.PowerState;
        this.values.set(key, `${fmt(s.percent() ?? NaN)} %, ${fmt(s.joules() ?? NaN)} J, ${fmt(s.watts() ?? NaN)} W`);
        return;
      }
      case W.Body.CameraImage: {
        this.onImage(key, msg.body(new W.CameraImage()) as W.CameraImage);
        return;
      }
      case W.Body.BumperState: {
        const s = msg.body(new W.BumperState()) as W.BumperState;
        this.values.set(key, `bumpers ${s.pressed().toString(2)}`);
        return;
      }
    }
  }

  private onImage(key: string, s: W.CameraImage): void {
    const width = s.width(), height = s.height(), format = s.format();
    const bytes = s.dataArray() ?? new Uint8Array();
    this.values.set(key, `${width}x${height} ${W.PixelFormat[format]}, ${W.ImageCompression[s.compression()]}, ` +
                         `${bytes.length} bytes`);
    const n = (this.cameraImages.get(key) ?? 0) + 1;
    this.cameraImages.set(key, n);
    if (s.compression() === W.ImageCompression.Png) {
      // No colour management: the canvas gets the camera's own values.
      createImageBitmap(new Blob([bytes.slice()], { type: 'image/png' }), { colorSpaceConversion: 'none' })
        .then((image) => {
          if (this.cameraImages.get(key) === n) this.cameras.set(key, { width, height, image });
        })
        .catch((e) => this.values.set(key, `image not decoded: ${e.message ?? e}`));
      return;
    }
    const stride = s.stride();
    const bpp = format === W.PixelFormat.Rgb8 ? 3 : format === W.PixelFormat.Mono8 ? 1 : 0;
    if (bpp === 0 || bytes.length < stride * (height - 1) + width * bpp) {
      this.cameras.delete(key); // depth: numbers in the panel, no picture
      return;
    }
    const image = new ImageData(width, height);
    const green = bpp === 3 ? 1 : 0, blue = bpp === 3 ? 2 : 0; // grey: the one byte three times
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        const at = y * stride + x * bpp, to = 4 * (y * width + x);
        image.data[to] = bytes[at];
        image.data[to + 1] = bytes[at + green];
        image.data[to + 2] = bytes[at + blue];
        image.data[to + 3] = 255;
      }
    }
    this.cameras.set(key, { width, height, image });
  }

  /// True when robots are placed by their odometry (a node), not by
  /// simulation:0's ground truth.
  odometryPoses = false;
}

export function fmt(v: number | undefined | null): string {
  return v === undefined || v === null || Number.isNaN(v) ? '-' : v.toFixed(2);
}
