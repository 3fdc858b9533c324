// The WebSocket stream of mobotd: connects with ?token=, subscribes on hello, decodes JSON and
// binary frames, measures latency (ping/pong and wall_us), and reconnects with exponential backoff.

import { costmapFromJson } from './costmap';
import type { Costmap, JsonCostmap } from './costmap';
import { cameraFromJson, cloudFromJson, decodeBinaryFrame, FrameError, mapFromJson, scanFromJson } from './frames';
import type { BinaryFrame, CloudChunk, FrameHeader, JsonCamera, JsonCloud, JsonMap, JsonScan, LaserScan, MapGrid } from './frames';
import { particlesFromJson } from './particles';
import type { JsonParticles, ParticleSet } from './particles';
import { backoffDelayMs, StreamStats } from './stats';
import { isTileJson, tilesFromJson } from './tiles';
import type { TileUpdate } from './tiles';

/**
 * Subscribed when the hello advertises them (ir, costmaps, particles and target: robots and builds
 * that have them). The `camera` topic is not among them: the Camera card subscribes to it itself,
 * thinned, only while it is shown on a robot that has a camera.
 */
export const WANTED_TOPICS = [
  'pose', 'odom', 'scan', 'sonar', 'ir', 'map', 'status', 'events', 'truth', 'goal', 'path', 'cloud',
  'costmap', 'local_costmap', 'particles', 'target',
];

/** Topics only some servers have: without a topic list in the hello they are not asked for. */
const OPTIONAL_TOPICS = ['truth', 'ir', 'costmap', 'local_costmap', 'particles', 'target'];

export type ConnectionState = 'connecting' | 'connected' | 'disconnected' | 'auth_error';

export interface HelloTopic {
  name: string;
  rate_hz?: number;
  encodings?: string[];
}

export interface Hello {
  op: 'hello';
  version?: number;
  topics?: HelloTopic[];
}

export interface FrameMeta {
  topic: string;
  t: number;
  seq?: number;
  wallUs?: number;
}

export interface StreamHandlers {
  state?(state: ConnectionState, detail: string): void;
  hello?(hello: Hello, subscribed: string[]): void;
  json?(topic: string, data: unknown, meta: FrameMeta): void;
  scan?(scan: LaserScan, meta: FrameMeta): void;
  map?(map: MapGrid, meta: FrameMeta): void;
  /** Changed tiles of the map being built (the `map` topic while mapping). */
  tiles?(update: TileUpdate, meta: FrameMeta): void;
  /** The global (`costmap`) or local (`local_costmap`) costmap; `which` tells them apart. */
  costmap?(costmap: Costmap, meta: FrameMeta): void;
  /** The particle filter's weighted sample (`particles`). */
  particles?(particles: ParticleSet, meta: FrameMeta): void;
  /** A chunk of a 3D sweep's point cloud (one tilting-laser scan). */
  cloud?(chunk: CloudChunk, meta: FrameMeta): void;
  /** One camera frame: the JPEG file (a view into the received message). */
  camera?(jpeg: Uint8Array, meta: FrameMeta): void;
  /** `{"op":"error"}` replies: unknown op/topic, teleop refused (estop_engaged, forbidden) ... */
  serverError?(code: string, message: string): void;
  teleopAck?(v: number, w: number): void;
  pong?(rttMs: number): void;
}

/** Decides, after a connection failed before opening, whether the token is the reason. */
export type AuthProbe = () => Promise<'ok' | 'unauthorized' | 'unreachable'>;

export interface StreamOptions {
  url: () => string;
  handlers: StreamHandlers;
  authProbe?: AuthProbe;
  pingIntervalMs?: number;
  /** No message for this long while connected: the socket is considered dead and reopened. */
  silenceTimeoutMs?: number;
  maxBackoffMs?: number;
}

export class StreamClient {
  readonly stats = new StreamStats();
  state: ConnectionState = 'disconnected';
  rttMs: number | null = null;
  subscribed: string[] = [];
  reconnects = 0;

  private socket: WebSocket | null = null;
  private attempt = 0;
  private opened = false;
  private stopped = true;
  private reconnectTimer: number | undefined;
  private pingTimer: number | undefined;
  private pingId = 0;
  private readonly pendingPings = new Map<number, number>();
  private lastMessageAt = 0;

  constructor(private readonly options: StreamOptions) {}

  start(): void {
    this.stopped = false;
    this.attempt = 0;
    this.open();
  }

  stop(): void {
    this.stopped = true;
    window.clearTimeout(this.reconnectTimer);
    this.closeSocket();
    this.setState('disconnected', 'stopped');
  }

  /** Reconnects now (e.g. after the token changed). */
  restart(): void {
    this.stop();
    this.start();
  }

  get connected(): boolean {
    return this.state === 'connected';
  }

  /** Sends one JSON op; false when the socket is not open. */
  send(message: object): boolean {
    if (!this.socket || this.socket.readyState !== WebSocket.OPEN) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }

  private setState(state: ConnectionState, detail = ''): void {
    this.state = state;
    this.options.handlers.state?.(state, detail);
  }

  private open(): void {
    window.clearTimeout(this.reconnectTimer);
    this.closeSocket();
    this.opened = false;
    this.setState('connecting', this.attempt > 0 ? `retry ${this.attempt}` : '');
    let socket: WebSocket;
    try {
      socket = new WebSocket(this.options.url());
    } catch (error) {
      this.setState('disconnected', String(error));
      this.scheduleReconnect();
      return;
    }
    socket.binaryType = 'arraybuffer';
    this.socket = socket;
    socket.onopen = () => {
      if (socket !== this.socket) return;
      this.opened = true;
      this.attempt = 0;
      this.lastMessageAt = performance.now();
      this.stats.resetSequences();
      this.setState('connected');
      this.startPings();
    };
    socket.onmessage = (event: MessageEvent) => {
      if (socket !== this.socket) return;
      this.lastMessageAt = performance.now();
      if (typeof event.data === 'string') this.onText(event.data);
      else if (event.data instanceof ArrayBuffer) this.onBinary(event.data);
    };
    socket.onclose = (event: CloseEvent) => {
      if (socket !== this.socket) return;
      this.socket = null;
      this.stopPings();
      void this.onClosed(event);
    };
    socket.onerror = () => {
      // onclose follows and does the work.
    };
  }

  private async onClosed(event: CloseEvent): Promise<void> {
    const wasOpen = this.opened;
    this.opened = false;
    this.subscribed = [];
    if (this.stopped) return;
    const reason = event.reason ? `${event.reason} (${event.code})` : `closed (${event.code})`;
    this.setState('disconnected', reason);
    if (!wasOpen && this.options.authProbe) {
      // A refused upgrade (401) looks like any other failure to the WebSocket API: ask REST.
      const verdict = await this.options.authProbe();
      if (this.stopped) return;
      if (verdict === 'unauthorized') {
        this.setState('auth_error', 'the server refused the token');
        this.stopped = true;
        return;
      }
    }
    this.scheduleReconnect();
  }

  private scheduleReconnect(): void {
    if (this.stopped) return;
    const delay = backoffDelayMs(this.attempt, 250, this.options.maxBackoffMs ?? 2000, 0.2);
    this.attempt++;
    this.reconnects++;
    window.clearTimeout(this.reconnectTimer);
    this.reconnectTimer = window.setTimeout(() => this.open(), delay);
  }

  private closeSocket(): void {
    this.stopPings();
    const socket = this.socket;
    this.socket = null;
    if (socket) {
      socket.onopen = socket.onmessage = socket.onclose = socket.onerror = null;
      try {
        socket.close(1000, 'client closing');
      } catch {
        // already closed
      }
    }
  }

  private startPings(): void {
    this.stopPings();
    const interval = this.options.pingIntervalMs ?? 1000;
    const silence = this.options.silenceTimeoutMs ?? 5000;
    this.pingTimer = window.setInterval(() => {
      if (performance.now() - this.lastMessageAt > silence) {
        // Half-open connection (e.g. the network vanished): drop it and reconnect.
        const socket = this.socket;
        this.socket = null;
        this.closeSocketQuietly(socket);
        this.stopPings();
        this.subscribed = [];
        this.setState('disconnected', 'no data from the server');
        this.scheduleReconnect();
        return;
      }
      const id = ++this.pingId;
      this.pendingPings.set(id, performance.now());
      if (this.pendingPings.size > 20) {
        const oldest = this.pendingPings.keys().next().value;
        if (oldest !== undefined) this.pendingPings.delete(oldest);
      }
      this.send({ op: 'ping', id });
      this.stats.tick(Date.now());
    }, interval);
  }

  private closeSocketQuietly(socket: WebSocket | null): void {
    if (!socket) return;
    socket.onopen = socket.onmessage = socket.onclose = socket.onerror = null;
    try {
      socket.close();
    } catch {
      // ignore
    }
  }

  private stopPings(): void {
    window.clearInterval(this.pingTimer);
    this.pingTimer = undefined;
    this.pendingPings.clear();
  }

  private onText(text: string): void {
    let message: Record<string, unknown>;
    try {
      message = JSON.parse(text) as Record<string, unknown>;
    } catch {
      return;
    }
    const handlers = this.options.handlers;
    if (typeof message.op === 'string') {
      switch (message.op) {
        case 'hello':
          this.onHello(message as unknown as Hello);
          return;
        case 'pong': {
          const sent = this.pendingPings.get(Number(message.id));
          if (sent !== undefined) {
            this.pendingPings.delete(Number(message.id));
            const rtt = performance.now() - sent;
            this.rttMs = this.rttMs === null ? rtt : 0.7 * this.rttMs + 0.3 * rtt;
            handlers.pong?.(rtt);
          }
          return;
        }
        case 'subscribed':
          if (Array.isArray(message.topics)) {
            for (const topic of message.topics as string[]) {
              if (!this.subscribed.includes(topic)) this.subscribed.push(topic);
            }
          }
          return;
        case 'unsubscribed':
          if (Array.isArray(message.topics)) {
            const gone = message.topics as string[];
            this.subscribed = this.subscribed.filter((topic) => !gone.includes(topic));
          }
          return;
        case 'error':
          handlers.serverError?.(String(message.code ?? 'error'), String(message.message ?? ''));
          return;
        case 'teleop':
          handlers.teleopAck?.(Number(message.v), Number(message.w));
          return;
        default:
          return;
      }
    }
    const topic = message.topic;
    if (typeof topic !== 'string') return;
    const meta: FrameMeta = {
      topic,
      t: Number(message.t),
      seq: typeof message.seq === 'number' ? message.seq : undefined,
      wallUs: typeof message.wall_us === 'number' ? message.wall_us : undefined,
    };
    this.stats.record(topic, meta.seq, topic === 'map' ? undefined : meta.wallUs, Date.now(), text.length);
    try {
      if (topic === 'scan' && handlers.scan) handlers.scan(scanFromJson(message.data as JsonScan), meta);
      else if (topic === 'map' && isTileJson(message.data)) handlers.tiles?.(tilesFromJson(message.data), meta);
      else if (topic === 'map' && handlers.map) handlers.map(mapFromJson(message.data as JsonMap), meta);
      else if (topic === 'cloud' && handlers.cloud) handlers.cloud(cloudFromJson(message.data as JsonCloud), meta);
      else if ((topic === 'costmap' || topic === 'local_costmap') && handlers.costmap) handlers.costmap(costmapFromJson(message.data as JsonCostmap), meta);
      else if (topic === 'particles' && handlers.particles) handlers.particles(particlesFromJson(message.data as JsonParticles), meta);
      else if (topic === 'camera' && handlers.camera) handlers.camera(cameraFromJson(message.data as JsonCamera), meta);
      else handlers.json?.(topic, message.data, meta);
    } catch (error) {
      console.warn(`mobot: bad ${topic} frame`, error);
    }
  }

  private onBinary(buffer: ArrayBuffer): void {
    let frame: BinaryFrame;
    try {
      frame = decodeBinaryFrame(buffer);
    } catch (error) {
      if (error instanceof FrameError) {
        console.warn('mobot: bad binary frame:', error.message);
        return;
      }
      throw error;
    }
    const header: FrameHeader = frame.header;
    // Both costmap topics share binary topic id 4: the body's `which` names the topic (and its seq).
    const topic = frame.kind === 'costmap' && frame.costmap.which === 'local' ? 'local_costmap' : header.topic;
    const meta: FrameMeta = { topic, t: header.t, seq: header.seq, wallUs: header.wallUs };
    // The map is re-sent on subscribe with its original stamp: its wall_us is an age, not a lag.
    const wallUs = frame.kind === 'map' ? undefined : header.wallUs;
    this.stats.record(topic, header.seq, wallUs, Date.now(), buffer.byteLength);
    const handlers = this.options.handlers;
    switch (frame.kind) {
      case 'scan':
        handlers.scan?.(frame.scan, meta);
        break;
      case 'map':
        handlers.map?.(frame.map, meta);
        break;
      case 'tiles':
        handlers.tiles?.(frame.tiles, meta);
        break;
      case 'cloud':
        handlers.cloud?.(frame.cloud, meta);
        break;
      case 'costmap':
        handlers.costmap?.(frame.costmap, meta);
        break;
      case 'particles':
        handlers.particles?.(frame.particles, meta);
        break;
      case 'camera':
        handlers.camera?.(frame.jpeg, meta);
        break;
      default:
        break;
    }
  }

  private onHello(hello: Hello): void {
    const advertised = Array.isArray(hello.topics) ? hello.topics.map((t) => t.name) : null;
    const topics = WANTED_TOPICS.filter((name) =>
      advertised ? advertised.includes(name) : !OPTIONAL_TOPICS.includes(name),
    );
    this.send({ op: 'subscribe', topics, encoding: 'binary' });
    this.options.handlers.hello?.(hello, topics);
  }
}
