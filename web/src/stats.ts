// Per-topic stream statistics: frames per second, seq gaps (frames dropped for this client, or
// thinned by max_rate_hz) and publish-to-receipt latency from wall_us. Pure: time is passed in.

export interface TopicStat {
  frames: number;
  rateHz: number;
  gaps: number;
  lastSeq: number;
  latencyMs: number | null;
  bytes: number;
}

interface Window {
  start: number;
  count: number;
}

export class StreamStats {
  private readonly topics = new Map<string, TopicStat>();
  private readonly windows = new Map<string, Window>();

  constructor(private readonly windowMs = 1000) {}

  /** Records one received frame of `topic`. `nowMs` is the receipt time (Unix ms). */
  record(topic: string, seq: number | undefined, wallUs: number | undefined, nowMs: number, bytes = 0): void {
    let stat = this.topics.get(topic);
    if (!stat) {
      stat = { frames: 0, rateHz: 0, gaps: 0, lastSeq: 0, latencyMs: null, bytes: 0 };
      this.topics.set(topic, stat);
      this.windows.set(topic, { start: nowMs, count: 0 });
    }
    stat.frames++;
    stat.bytes += bytes;
    if (seq !== undefined && Number.isFinite(seq)) {
      if (stat.lastSeq > 0 && seq > stat.lastSeq + 1) stat.gaps += seq - stat.lastSeq - 1;
      // A seq that goes backwards is a restarted server: start counting again from it.
      stat.lastSeq = seq;
    }
    if (wallUs !== undefined && wallUs > 0) {
      const latency = nowMs - wallUs / 1000;
      stat.latencyMs = stat.latencyMs === null ? latency : 0.8 * stat.latencyMs + 0.2 * latency;
    }
    const window = this.windows.get(topic)!;
    window.count++;
    this.roll(topic, stat, window, nowMs);
  }

  /** Updates the rates of every topic at `nowMs`, so silent topics decay to zero. */
  tick(nowMs: number): void {
    for (const [topic, stat] of this.topics) this.roll(topic, stat, this.windows.get(topic)!, nowMs);
  }

  private roll(_topic: string, stat: TopicStat, window: Window, nowMs: number): void {
    const elapsed = nowMs - window.start;
    if (elapsed >= this.windowMs) {
      stat.rateHz = (window.count * 1000) / elapsed;
      window.start = nowMs;
      window.count = 0;
    }
  }

  /** Forgets the seq baselines (after a reconnect the server may have restarted). */
  resetSequences(): void {
    for (const stat of this.topics.values()) stat.lastSeq = 0;
  }

  /**
   * Forgets one topic's seq baseline: it was (un)subscribed again, and the frames published
   * while it was not subscribed were never meant for this client.
   */
  resetTopic(topic: string): void {
    const stat = this.topics.get(topic);
    if (stat) stat.lastSeq = 0;
  }

  /**
   * The seq gaps split by what they mean: `dropped` on topics subscribed at full rate (frames the
   * server dropped for this client, or lost), `thinned` on topics subscribed with max_rate_hz
   * (where a gap is mostly the thinning asked for).
   */
  gapsByKind(thinnedTopics: ReadonlySet<string>): { dropped: number; thinned: number } {
    let dropped = 0;
    let thinned = 0;
    for (const [topic, stat] of this.topics) {
      if (thinnedTopics.has(topic)) thinned += stat.gaps;
      else dropped += stat.gaps;
    }
    return { dropped, thinned };
  }

  get(topic: string): TopicStat | undefined {
    return this.topics.get(topic);
  }

  entries(): [string, TopicStat][] {
    return [...this.topics.entries()].sort(([a], [b]) => a.localeCompare(b));
  }

  totalGaps(): number {
    let total = 0;
    for (const stat of this.topics.values()) total += stat.gaps;
    return total;
  }
}

/** Exponential reconnect delay: 250 ms, 500 ms, 1 s, 2 s, 2 s, ... (by default) with a little jitter. */
export function backoffDelayMs(attempt: number, baseMs = 250, maxMs = 2000, jitter = 0): number {
  const delay = Math.min(maxMs, baseMs * 2 ** Math.max(0, attempt));
  return Math.round(delay * (1 - jitter / 2 + jitter * Math.random()));
}
