// The WebSocket stream of mobotd: connects with ?token=, subscribes on hello, decodes JSON and
// binary frames, numbers the teleop commands (a lease each, docs/api.md "The teleop lease"),
// measures the link (app-level pings every second; bytes received), notices a stalled link (no
// message at all for STALL_MS) and reconnects with exponential backoff, except after the server
// closed with 4401 (the token was revoked or expired).

import { costmapFromJson } from './costmap';
import type { Costmap, JsonCostmap } from './costmap';
import { cameraFromJson, cloudFromJson, decodeBinaryFrame, FrameError, mapFromJson, scanFromJson } from './frames';
import type { BinaryFrame, CloudChunk, FrameHeader, JsonCamera, JsonCloud, JsonMap, JsonScan, LaserScan, MapGrid } from './frames';
import { particlesFromJson } from './particles';
import type { JsonParticles, ParticleSet } from './particles';
import { localWallMs } from './clock_offset';
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

/** Why the stream stopped for good: the upgrade was refused (401), or the server closed with 4401. */
export type AuthFailure = 'refused' | 'revoked';

/** Reconnect delays: 0.5, 1, 2, 4, 5, 5 ... s (a little jitter so many pages do not come back at once). */
export const RECONNECT_BASE_MS = 500;
export const RECONNECT_MAX_MS = 5000;
/**
 * No message at all for this long and the link is stalled: pongs answer the pings every second
 * and the pose comes at 50 Hz, so 2 s of silence is no quiet robot.
 */
export const STALL_MS = 2000;
/** How often the silence is looked at. */
const LIVENESS_CHECK_MS = 250;
/**
 * A liveness check this late means the page itself was frozen (a long task, a background tab):
 * its silence says nothing about the link, so the silence is measured again from then.
 */
const FROZEN_PAGE_MS = 1500;
/** The close code of a token that was revoked or has expired (docs/api.md). */
export const CLOSE_TOKEN_REVOKED = 4401;

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
  /**
   * `{"op":"error"}` replies: unknown op/topic, teleop refused (estop_engaged, forbidden) ...;
   * `requestOp` is the op of the request it refuses, when the server could tell.
   */
  serverError?(code: string, message: string, requestOp?: string): void;
  /** A teleop command applied by the control loop; its round trip when the echo carries `sent_ms`. */
  teleopAck?(ack: TeleopAck): void;
  /** The e-stop state after a stream `{"op":"estop"}` of this page was carried out. */
  estopAck?(engaged: boolean): void;
  pong?(pong: Pong): void;
}

export interface TeleopAck {
  v: number;
  w: number;
  seq: number | null;
  /** performance.now() at sending minus at the echo; null when the echo has no `sent_ms`. */
  rttMs: number | null;
}

export interface Pong {
  /** Local wall clock (ms, localWallMs) when the ping left and when its pong arrived. */
  sentMs: number;
  receivedMs: number;
  /** The server's wall clock when it answered (Unix us); absent on servers that do not send it. */
  wallUs?: number;
}

/** Decides, after a connection failed before opening, whether the token is the reason. */
export type AuthProbe = () => Promise<'ok' | 'unauthorized' | 'unreachable'>;

export interface StreamOptions {
  url: () => string;
  handlers: StreamHandlers;
  authProbe?: AuthProbe;
  pingIntervalMs?: number;
  /** No message for this long while connected: the link is stalled, the socket is dropped and reopened. */
  stallMs?: number;
  maxBackoffMs?: number;
}

export class StreamClient {
  readonly stats = new StreamStats();
  state: ConnectionState = 'disconnected';
  rttMs: number | null = null;
  subscribed: string[] = [];
  reconnects = 0;
  /** Reconnect attempts since the last open connection (0 while connected). */
  attempt = 0;
  /** performance.now() of the next reconnect attempt; null when none is scheduled. */
  nextAttemptAt: number | null = null;
  /** Why the stream stopped for good (auth_error); null otherwise. */
  authFailure: AuthFailure | null = null;
  /** Every byte received on every connection (text frames counted by their length). */
  bytesReceived = 0;
  /** Topics subscribed with max_rate_hz on this connection: their seq gaps are thinning, not loss. */
  readonly thinnedTopics = new Set<string>();
  /** The last teleop `seq` sent on this connection (0: none yet); each connection starts at 1. */
  teleopSeq = 0;
  /** Teleop echoes received (all connections). */
  teleopAcks = 0;

  private socket: WebSocket | null = null;
  private opened = false;
  private stopped = true;
  private reconnectTimer: number | undefined;
  private pingTimer: number | undefined;
  private livenessTimer: number | undefined;
  private pingId = 0;
  private readonly pendingPings = new Map<number, number>();
  private lastMessageAt = 0;
  private lastCheckAt = 0;

  constructor(private readonly options: StreamOptions) {}

  start(): void {
    this.stopped = false;
    this.attempt = 0;
    this.authFailure = null;
    this.open();
  }

  stop(): void {
    this.stopped = true;
    window.clearTimeout(this.reconnectTimer);
    this.nextAttemptAt = null;
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

  /**
   * Sends one JSON op; false when the socket is not open. Nothing is queued for later: a message
   * that cannot go now is dropped (a joystick command replayed after a reconnect would be stale).
   */
  send(message: object): boolean {
    if (!this.socket || this.socket.readyState !== WebSocket.OPEN) return false;
    this.socket.send(JSON.stringify(message));
    this.noteSubscription(message as Record<string, unknown>);
    return true;
  }

  /**
   * One teleop command, a lease of `ttlMs`: numbered on this connection (`seq`, from 1) and
   * stamped with performance.now() (`sent_ms`), which the server echoes for the round trip.
   */
  sendTeleop(v: number, w: number, ttlMs: number): boolean {
    if (!this.connected) return false;
    const seq = this.teleopSeq + 1;
    const sent = this.send({ op: 'teleop', v, w, ttl_ms: ttlMs, seq, sent_ms: Math.round(performance.now() * 1000) / 1000 });
    if (sent) this.teleopSeq = seq;
    return sent;
  }

  /** Subscriptions decide what a seq gap means; a topic (re)subscribed counts from its next frame. */
  private noteSubscription(message: Record<string, unknown>): void {
    if ((message.op !== 'subscribe' && message.op !== 'unsubscribe') || !Array.isArray(message.topics)) return;
    const thinned = message.op === 'subscribe' && typeof message.max_rate_hz === 'number';
    for (const topic of message.topics) {
      if (typeof topic !== 'string') continue;
      if (thinned) this.thinnedTopics.add(topic);
      else this.thinnedTopics.delete(topic);
      this.stats.resetTopic(topic);
    }
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
      this.nextAttemptAt = null;
      this.teleopSeq = 0;
      this.thinnedTopics.clear();
      this.lastMessageAt = performance.now();
      this.stats.resetSequences();
      this.setState('connected');
      this.startPings();
    };
    socket.onmessage = (event: MessageEvent) => {
      if (socket !== this.socket) return;
      this.lastMessageAt = performance.now();
      if (typeof event.data === 'string') {
        this.bytesReceived += event.data.length;
        this.onText(event.data);
      } else if (event.data instanceof ArrayBuffer) {
        this.bytesReceived += event.data.byteLength;
        this.onBinary(event.data);
      }
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
    if (event.code === CLOSE_TOKEN_REVOKED) {
      // Trying again with the same token would only be refused: the person has to sign in.
      this.fail('revoked', event.reason || 'the token was revoked or has expired');
      return;
    }
    const reason = event.reason ? `${event.reason} (${event.code})` : `closed (${event.code})`;
    this.setState('disconnected', reason);
    if (!wasOpen && this.options.authProbe) {
      // A refused upgrade (401) looks like any other failure to the WebSocket API: ask REST.
      const verdict = await this.options.authProbe();
      if (this.stopped) return;
      if (verdict === 'unauthorized') {
        this.fail('refused', 'the server refused the token');
        return;
      }
    }
    this.scheduleReconnect();
  }

  private fail(why: AuthFailure, detail: string): void {
    this.authFailure = why;
    this.stopped = true;
    this.nextAttemptAt = null;
    this.setState('auth_error', detail);
  }

  private scheduleReconnect(): void {
    if (this.stopped) return;
    const delay = backoffDelayMs(this.attempt, RECONNECT_BASE_MS, this.options.maxBackoffMs ?? RECONNECT_MAX_MS, 0.2);
    this.attempt++;
    this.reconnects++;
    this.nextAttemptAt = performance.now() + delay;
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
    this.lastCheckAt = performance.now();
    this.livenessTimer = window.setInterval(() => this.checkLiveness(), LIVENESS_CHECK_MS);
    this.pingTimer = window.setInterval(() => {
      const id = ++this.pingId;
      this.pendingPings.set(id, localWallMs());
      if (this.pendingPings.size > 20) {
        const oldest = this.pendingPings.keys().next().value;
        if (oldest !== undefined) this.pendingPings.delete(oldest);
      }
      this.send({ op: 'ping', id });
      this.stats.tick(localWallMs());
    }, interval);
  }

  /** No message for STALL_MS while the page ran: a stalled or half-open link; drop it and reconnect. */
  private checkLiveness(): void {
    const now = performance.now();
    if (now - this.lastCheckAt > FROZEN_PAGE_MS) this.lastMessageAt = Math.max(this.lastMessageAt, now);
    this.lastCheckAt = now;
    const stallMs = this.options.stallMs ?? STALL_MS;
    if (now - this.lastMessageAt <= stallMs) return;
    const socket = this.socket;
    this.socket = null;
    this.closeSocketQuietly(socket);
    this.stopPings();
    this.opened = false;
    this.subscribed = [];
    this.setState('disconnected', `stalled: no data for ${(stallMs / 1000).toFixed(0)} s`);
    this.scheduleReconnect();
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
    window.clearInterval(this.livenessTimer);
    this.pingTimer = undefined;
    this.livenessTimer = undefined;
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
            const received = localWallMs();
            const rtt = received - sent;
            this.rttMs = this.rttMs === null ? rtt : 0.7 * this.rttMs + 0.3 * rtt;
            const wallUs = typeof message.wall_us === 'number' && message.wall_us > 0 ? message.wall_us : undefined;
            handlers.pong?.({ sentMs: sent, receivedMs: received, wallUs });
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
          handlers.serverError?.(
            String(message.code ?? 'error'),
            String(message.message ?? ''),
            typeof message.request_op === 'string' ? message.request_op : undefined,
          );
          return;
        case 'teleop': {
          this.teleopAcks++;
          const sentMs = typeof message.sent_ms === 'number' ? message.sent_ms : null;
          const rtt = sentMs === null ? null : performance.now() - sentMs;
          handlers.teleopAck?.({
            v: Number(message.v),
            w: Number(message.w),
            seq: typeof message.seq === 'number' ? message.seq : null,
            // sent_ms is this page's performance.now(): an echo that is not one is no round trip.
            rttMs: rtt !== null && rtt >= 0 && rtt < 60_000 ? rtt : null,
          });
          return;
        }
        case 'estop':
          if (typeof message.engaged === 'boolean') handlers.estopAck?.(message.engaged);
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
    this.stats.record(topic, meta.seq, topic === 'map' ? undefined : meta.wallUs, localWallMs(), text.length);
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
    this.stats.record(topic, header.seq, wallUs, localWallMs(), buffer.byteLength);
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
