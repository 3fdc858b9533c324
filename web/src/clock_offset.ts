// The server's wall clock as seen from this page, so that a frame's `wall_us` (when the server
// published it) says how old the frame is here even when the two clocks disagree. Each pong that
// carries the server's `wall_us` gives one estimate, offset = server_wall - (t_send + t_recv) / 2,
// wrong by at most half that ping's round trip (the answer was written somewhere between send and
// receipt); the estimate kept is the one of the fastest pong of the last WINDOW_MS, so a queue in
// the network inflates nothing. Pure: the times are passed in.

/** Estimates older than this are not used: clocks drift, and the path may have changed. */
export const OFFSET_WINDOW_MS = 30_000;

/** This page's wall clock (Unix ms) from the monotonic clock, so that it never steps. */
export function localWallMs(): number {
  return performance.timeOrigin + performance.now();
}

export interface OffsetEstimate {
  /** Server wall clock minus this page's (ms): server = local + offsetMs. */
  offsetMs: number;
  /** The round trip of the pong it came from: the estimate is good to +- half of it. */
  rttMs: number;
  /** Local wall clock (ms) when that pong arrived. */
  atMs: number;
}

export class ClockOffset {
  private samples: OffsetEstimate[] = [];

  constructor(private readonly windowMs = OFFSET_WINDOW_MS) {}

  /** A pong: the ping left at `sentMs`, its answer arrived at `receivedMs` (local wall ms). */
  add(sentMs: number, receivedMs: number, serverWallUs: number): void {
    if (!Number.isFinite(serverWallUs) || serverWallUs <= 0 || !(receivedMs >= sentMs)) return;
    this.samples.push({ offsetMs: serverWallUs / 1000 - (sentMs + receivedMs) / 2, rttMs: receivedMs - sentMs, atMs: receivedMs });
    this.prune(receivedMs);
  }

  /** The estimate of the fastest pong within the window before `nowMs`; null when none. */
  best(nowMs: number): OffsetEstimate | null {
    this.prune(nowMs);
    let best: OffsetEstimate | null = null;
    for (const s of this.samples) if (!best || s.rttMs < best.rttMs) best = s;
    return best;
  }

  /** Forget everything (another server, or after a reconnect the path may differ). */
  reset(): void {
    this.samples = [];
  }

  private prune(nowMs: number): void {
    const oldest = nowMs - this.windowMs;
    if (this.samples.length && this.samples[0]!.atMs < oldest) this.samples = this.samples.filter((s) => s.atMs >= oldest);
  }
}

/**
 * How old a frame published at `wallUs` (server clock) is at local `nowMs`: translated with the
 * offset when there is one, else taken as if both clocks agreed (the same machine, or NTP).
 */
export function frameAgeMs(wallUs: number, nowMs: number, offset: OffsetEstimate | null): number {
  return nowMs - (wallUs / 1000 - (offset?.offsetMs ?? 0));
}
