// The wire protocol over a WebSocket: one binary message is one frame
// (size prefix included), exactly as on the node's TCP port. The server
// bridges it to the node unchanged, so this is a Troupe client like any other.
// When the socket closes (the simulator or node restarted, the network
// dropped) it connects again by itself, waiting longer after each failed
// attempt, as the C++ client library and passthrough do.
import * as flatbuffers from 'flatbuffers';
import * as W from 'troupe-wire';

/// Wire protocol version spoken (Hello.protocol_version).
const kProtocolVersion = 1;
/// Largest frame accepted, bytes (the node's default limit).
const kMaxFrameBytes = 1 << 20;
/// Reconnection backoff: the first retry after kRetryMinMs, each failed
/// attempt doubles the wait up to kRetryMaxMs; a connection that opened
/// starts again from the minimum. ms.
const kRetryMinMs = 250;
const kRetryMaxMs = 5000;

/// Where the connection stands: opening a socket, open, or waiting before
/// the next attempt.
export type LinkState = 'connecting' | 'open' | 'waiting';

export interface Address {
  robot: number;
  iface: number;
  index: number;
}

export interface DeviceEntry {
  addr: Address;
  robotName: string;
  driver: string;
  /// "r0/ranger:1" or "simulation:0", as the CLI writes it.
  text: string;
}

/// A reply: the Ack's message, or an Error for a Nack.
export class RequestFailed extends Error {}

type Pending = { resolve: (m: W.Message) => void; reject: (e: Error) => void };
export type DataHandler = (msg: W.Message, addr: Address) => void;

export const ifaceNames: Record<number, string> = {
  1: 'position2d', 2: 'ranger', 3: 'power', 4: 'bumper', 5: 'blobfinder', 6: 'fiducial', 7: 'actuator',
  8: 'imu', 9: 'localize', 10: 'map', 11: 'simulation', 12: 'opaque', 13: 'camera',
};

export function addrKey(a: Address): string {
  return `${a.robot}/${a.iface}:${a.index}`;
}

export class Connection {
  private ws!: WebSocket;
  private seq = 1;
  private pending = new Map<number, Pending>();
  private retryMs = kRetryMinMs;
  private retryTimer: ReturnType<typeof setTimeout> | undefined;
  private stopped = false;
  /// Called for every Data frame.
  onData: DataHandler = () => {};
  /// Called each time the connection ends, with the reason; a new attempt
  /// follows by itself (see state).
  onClose: (reason: string) => void = () => {};
  /// Called on every change of state.
  onState: (state: LinkState) => void = () => {};
  state: LinkState = 'connecting';
  /// Attempts since the last open connection (0 while open).
  failedAttempts = 0;
  /// When the next attempt starts (performance.now() ms), while waiting.
  retryAt = 0;
  /// Connections opened so far (1 after the first; more after restarts).
  opens = 0;
  nodeName = '';
  framesIn = 0;
  /// Requests still waiting for their reply.
  get pendingCount(): number {
    return this.pending.size;
  }

  /// `onOpen` runs for every connection opened: the first and each one
  /// after a restart, where the page learns the world again.
  constructor(private url: string, private onOpen: () => void) {
    this.connect();
  }

  private setState(state: LinkState): void {
    this.state = state;
    this.onState(state);
  }

  private connect(): void {
    this.retryTimer = undefined;
    this.setState('connecting');
    const ws = new WebSocket(this.url);
    this.ws = ws;
    ws.binaryType = 'arraybuffer';
    ws.onopen = () => {
      this.retryMs = kRetryMinMs;
      this.failedAttempts = 0;
      ++this.opens;
      this.nodeName = '';
      this.setState('open');
      this.sendHello();
      this.onOpen();
    };
    ws.onmessage = (ev) => {
      if (ws === this.ws) this.receive(new Uint8Array(ev.data as ArrayBuffer));
    };
    ws.onclose = (ev) => {
      if (ws !== this.ws) return;
      const why = ev.reason || `connection closed (code ${ev.code})`;
      for (const p of this.pending.values()) p.reject(new RequestFailed(why));
      this.pending.clear();
      this.onClose(why);
      this.scheduleRetry();
    };
  }

  private scheduleRetry(): void {
    if (this.stopped) return;
    ++this.failedAttempts;
    this.retryAt = performance.now() + this.retryMs;
    this.retryTimer = setTimeout(() => this.connect(), this.retryMs);
    this.retryMs = Math.min(this.retryMs * 2, kRetryMaxMs);
    this.setState('waiting');
  }

  /// Closes for good: no more attempts.
  close(): void {
    this.stopped = true;
    if (this.retryTimer !== undefined) clearTimeout(this.retryTimer);
    this.ws.close();
  }

  private now(): bigint {
    return BigInt(Math.round(performance.now() * 1000));
  }

  /// Builds and sends one frame; `body` adds the body and returns its type.
  private send(kind: W.Kind, addr: Address, subtype: number, seq: number,
               body?: (b: flatbuffers.Builder) => [W.Body, flatbuffers.Offset]): void {
    if (this.ws.readyState !== WebSocket.OPEN) {  // between connections: the request fails now
      const p = this.pending.get(seq);
      this.pending.delete(seq);
      p?.reject(new RequestFailed('not connected'));
      return;
    }
    const b = new flatbuffers.Builder(256);
    let type = W.Body.NONE;
    let offset = 0;
    if (body) [type, offset] = body(b);
    const t = this.now();
    W.Message.startMessage(b);
    W.Message.addBodyType(b, type);
    W.Message.addHeader(b, W.Header.createHeader(b, addr.robot, addr.iface, addr.index, kind, subtype, seq,
                                                 Number(t & 0xffffffffn), Number(t >> 32n)));
    if (body) W.Message.addBody(b, offset);
    W.Message.finishSizePrefixedMessageBuffer(b, W.Message.endMessage(b));
    this.ws.send(b.asUint8Array());
  }

  private sendHello(): void {
    this.send(W.Kind.Hello, { robot: 0, iface: 0, index: 0 }, 0, 0, (b) => {
      const name = b.createString('troupe-viewer');
      return [W.Body.Hello, W.Hello.createHello(b, kProtocolVersion, name, kMaxFrameBytes, 0, this.now())];
    });
  }

  private expect(seq: number): Promise<W.Message> {
    return new Promise((resolve, reject) => this.pending.set(seq, { resolve, reject }));
  }

  /// Sends raw bytes (the tests' bad input).
  sendRaw(bytes: Uint8Array): void {
    if (this.ws.readyState === WebSocket.OPEN) this.ws.send(bytes);
  }

  async deviceList(): Promise<DeviceEntry[]> {
    const seq = this.seq++;
    const reply = this.expect(seq);
    this.send(W.Kind.DeviceList, { robot: 0, iface: 0, index: 0 }, 0, seq);
    const msg = await reply;
    const list = msg.body(new W.DeviceList()) as W.DeviceList;
    const out: DeviceEntry[] = [];
    for (let i = 0; i < list.devicesLength(); ++i) {
      const d = list.devices(i)!;
      const a = d.addr()!;
      const addr = { robot: a.robot(), iface: a.iface(), index: a.index() };
      const robotName = d.robotName() || '';
      const name = `${ifaceNames[addr.iface] || 'iface' + addr.iface}:${addr.index}`;
      out.push({ addr, robotName, driver: d.driver() || '', text: robotName ? `${robotName}/${name}` : name });
    }
    return out;
  }

  /// Opens a device for reading (Data pushed) or for everything; a camera
  /// packs its images as `compression` asks (the browser decodes PNG).
  async open(addr: Address, access: W.Access = W.Access.Read,
             compression: W.ImageCompression = W.ImageCompression.None): Promise<void> {
    const seq = this.seq++;
    const reply = this.expect(seq);
    this.send(W.Kind.Open, addr, 0, seq, (b) => [W.Body.Open, W.Open.createOpen(b, access, W.Delivery.Push, compression)]);
    await reply;
  }

  /// Stops reading a device (its sensor may then stop being computed).
  async closeDevice(addr: Address): Promise<void> {
    const seq = this.seq++;
    const reply = this.expect(seq);
    this.send(W.Kind.Close, addr, 0, seq);
    await reply;
  }

  /// A Request; resolves with the Ack, rejects with the Nack's text.
  async request(addr: Address, subtype: number,
                body?: (b: flatbuffers.Builder) => [W.Body, flatbuffers.Offset]): Promise<W.Message> {
    const seq = this.seq++;
    const reply = this.expect(seq);
    this.send(W.Kind.Request, addr, subtype, seq, body);
    return reply;
  }

  private receive(bytes: Uint8Array): void {
    ++this.framesIn;
    const bb = new flatbuffers.ByteBuffer(bytes);
    const msg = W.Message.getSizePrefixedRootAsMessage(bb);
    const h = msg.header();
    const a = h?.addr();
    if (!h || !a) return;
    const addr = { robot: a.robot(), iface: a.iface(), index: a.index() };
    switch (h.kind()) {
      case W.Kind.Data:
        this.onData(msg, addr);
        return;
      case W.Kind.Hello: {
        const hello = msg.body(new W.Hello()) as W.Hello | null;
        this.nodeName = hello?.name() || '';
        return;
      }
      case W.Kind.Ack:
      case W.Kind.DeviceList:
      case W.Kind.Nack: {
        const p = this.pending.get(h.seq());
        if (!p) return;
        this.pending.delete(h.seq());
        if (h.kind() === W.Kind.Nack) {
          const e = msg.body(new W.Error()) as W.Error | null;
          p.reject(new RequestFailed(e?.text() || 'refused'));
        } else {
          p.resolve(msg);
        }
        return;
      }
      case W.Kind.Error: {
        const e = msg.body(new W.Error()) as W.Error | null;
        console.warn('node error:', e?.text());
        return;
      }
    }
  }
}
