import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { CLOSE_TOKEN_REVOKED, RECONNECT_MAX_MS, STALL_MS, StreamClient } from '../src/stream';
import type { ConnectionState, Pong, TeleopAck } from '../src/stream';

/** A WebSocket the test opens, feeds and closes. */
class FakeSocket {
  static readonly OPEN = 1;
  static instances: FakeSocket[] = [];
  readyState = 0;
  binaryType = '';
  readonly sent: Record<string, unknown>[] = [];
  onopen: (() => void) | null = null;
  onmessage: ((e: { data: unknown }) => void) | null = null;
  onclose: ((e: { code: number; reason: string }) => void) | null = null;
  onerror: (() => void) | null = null;

  constructor(readonly url: string) {
    FakeSocket.instances.push(this);
  }
  send(data: string): void {
    this.sent.push(JSON.parse(data) as Record<string, unknown>);
  }
  close(): void {
    this.readyState = 3;
  }
  open(): void {
    this.readyState = 1;
    this.onopen?.();
  }
  receive(message: object): void {
    this.onmessage?.({ data: JSON.stringify(message) });
  }
  serverClose(code: number, reason = ''): void {
    this.readyState = 3;
    this.onclose?.({ code, reason });
  }
  ops(op: string): Record<string, unknown>[] {
    return this.sent.filter((m) => m.op === op);
  }
}

const last = () => FakeSocket.instances[FakeSocket.instances.length - 1]!;

function client() {
  const states: [ConnectionState, string][] = [];
  const acks: TeleopAck[] = [];
  const pongs: Pong[] = [];
  const stream = new StreamClient({
    url: () => 'ws://robot/api/v1/stream?token=t',
    handlers: {
      state: (state, detail) => states.push([state, detail]),
      teleopAck: (ack) => acks.push(ack),
      pong: (pong) => pongs.push(pong),
    },
  });
  return { stream, states, acks, pongs };
}

beforeEach(() => {
  FakeSocket.instances = [];
  vi.useFakeTimers({ toFake: ['setTimeout', 'clearTimeout', 'setInterval', 'clearInterval', 'performance'] });
  vi.stubGlobal('window', globalThis);
  vi.stubGlobal('WebSocket', FakeSocket);
});

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

describe('stream teleop leases', () => {
  it('numbers the commands of a connection from 1, stamps them, and starts again after a reconnect', () => {
    const { stream } = client();
    stream.start();
    expect(stream.sendTeleop(0.5, 0, 300)).toBe(false); // not open yet: dropped, not queued
    last().open();
    vi.advanceTimersByTime(100);
    expect(stream.sendTeleop(0.5, 0, 300)).toBe(true);
    expect(stream.sendTeleop(0.5, 0.1, 300)).toBe(true);
    const first = last().ops('teleop');
    expect(first.map((m) => m.seq)).toEqual([1, 2]);
    expect(first[0]).toMatchObject({ op: 'teleop', v: 0.5, w: 0, ttl_ms: 300 });
    expect(typeof first[0]!.sent_ms).toBe('number');
    last().serverClose(1006);
    expect(stream.sendTeleop(0.5, 0, 300)).toBe(false);
    vi.advanceTimersByTime(RECONNECT_MAX_MS);
    last().open();
    expect(last().ops('teleop')).toEqual([]); // nothing sent while down comes out now
    stream.sendTeleop(0.2, 0, 300);
    expect(last().ops('teleop').map((m) => m.seq)).toEqual([1]);
    stream.stop();
  });

  it('measures the command round trip from the echo of sent_ms', () => {
    const { stream, acks } = client();
    stream.start();
    last().open();
    stream.sendTeleop(0.5, 0, 300);
    const sent = last().ops('teleop')[0]!;
    vi.advanceTimersByTime(40);
    last().receive({ op: 'teleop', v: 0.5, w: 0, seq: sent.seq, sent_ms: sent.sent_ms });
    expect(acks).toHaveLength(1);
    expect(acks[0]!.seq).toBe(1);
    expect(acks[0]!.rttMs).toBeCloseTo(40, 0);
    stream.stop();
  });
});

describe('stream liveness', () => {
  it('pings every second and passes the server wall clock of the pong on', () => {
    const { stream, pongs } = client();
    stream.start();
    last().open();
    vi.advanceTimersByTime(1000);
    const ping = last().ops('ping')[0]!;
    vi.advanceTimersByTime(3);
    last().receive({ op: 'pong', id: ping.id, t: 1.5, wall_us: 1_800_000_000_000_000 });
    expect(pongs).toHaveLength(1);
    expect(pongs[0]!.receivedMs - pongs[0]!.sentMs).toBeCloseTo(3, 0);
    expect(pongs[0]!.wallUs).toBe(1_800_000_000_000_000);
    stream.stop();
  });

  it('drops a stalled link (no message for 2 s) and reconnects after 0.5 s', () => {
    const { stream, states } = client();
    stream.start();
    const first = last();
    first.open();
    // The server answers nothing, not even the pings.
    vi.advanceTimersByTime(STALL_MS + 300);
    expect(stream.state).toBe('disconnected');
    expect(states.some(([s, d]) => s === 'disconnected' && /stalled/.test(d))).toBe(true);
    expect(first.readyState).toBe(3);
    expect(stream.attempt).toBe(1);
    vi.advanceTimersByTime(600);
    expect(FakeSocket.instances.length).toBe(2);
    stream.stop();
  });

  it('backs off 0.5, 1, 2, 4, 5 s', () => {
    const { stream } = client();
    stream.start();
    const delays: number[] = [];
    for (let i = 0; i < 6; i++) {
      last().serverClose(1006);
      delays.push(stream.nextAttemptAt! - performance.now());
      vi.advanceTimersByTime(RECONNECT_MAX_MS * 1.2);
    }
    const expected = [500, 1000, 2000, 4000, 5000, 5000];
    delays.forEach((d, i) => expect(Math.abs(d - expected[i]!)).toBeLessThanOrEqual(expected[i]! * 0.1 + 1));
    stream.stop();
  });

  it('stops for good when the server closes with 4401 (token revoked or expired)', () => {
    const { stream } = client();
    stream.start();
    last().open();
    last().serverClose(CLOSE_TOKEN_REVOKED, 'token revoked');
    expect(stream.state).toBe('auth_error');
    expect(stream.authFailure).toBe('revoked');
    vi.advanceTimersByTime(30_000);
    expect(FakeSocket.instances.length).toBe(1);
  });
});

describe('what a seq gap means', () => {
  it('counts gaps of thinned topics apart from drops, from the next frame after a (re)subscribe', () => {
    const { stream } = client();
    stream.start();
    last().open();
    stream.send({ op: 'subscribe', topics: ['camera'], max_rate_hz: 10 });
    expect([...stream.thinnedTopics]).toEqual(['camera']);
    for (const [topic, seq] of [['pose', 1], ['pose', 2], ['pose', 4], ['camera', 10], ['camera', 13]] as const) {
      last().receive({ topic, t: 0, seq, wall_us: 1, data: topic === 'pose' ? { x: 0, y: 0, theta: 0, v: 0, w: 0 } : {} });
    }
    expect(stream.stats.gapsByKind(stream.thinnedTopics)).toEqual({ dropped: 1, thinned: 2 });
    // Unsubscribed and subscribed again much later: the publications in between are no gap.
    stream.send({ op: 'unsubscribe', topics: ['camera'] });
    stream.send({ op: 'subscribe', topics: ['camera'], max_rate_hz: 10 });
    last().receive({ topic: 'camera', t: 0, seq: 500, wall_us: 1, data: {} });
    expect(stream.stats.gapsByKind(stream.thinnedTopics)).toEqual({ dropped: 1, thinned: 2 });
    stream.stop();
  });
});
