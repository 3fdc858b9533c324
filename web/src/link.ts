// The link to the robot as the operator needs to judge it: the round trip (app-level pings every
// second, and the echoes of the teleop commands while driving), how old the pose and the scan on
// screen are (their `wall_us` translated to this page's clock with the offset the pongs give), the
// bytes received per second, and a 60 s history of it for the Link card's plot. Pure: times and
// byte counts are passed in; link_panel.ts renders it.

import { ClockOffset, frameAgeMs } from './clock_offset';
import type { OffsetEstimate } from './clock_offset';

/** The plot's history. */
export const PLOT_WINDOW_MS = 60_000;
/** One sample per period: 4 Hz is smooth enough to read and cheap to draw. */
export const SAMPLE_PERIOD_MS = 250;
/** A ping round trip older than this is not plotted: pings (every 1 s) stopped coming back. */
const PING_FRESH_MS = 2500;
/** Teleop echoes come at 15 Hz while driving; this long after the last one the series pauses. */
const TELEOP_FRESH_MS = 1000;
/** bytes/s is measured over about this long. */
const RATE_WINDOW_MS = 1000;

export type SeriesKey = 'pingRttMs' | 'teleopRttMs' | 'poseAgeMs' | 'scanAgeMs';

/** One point of the history; null where a series has no value (not measured then). */
export type LinkSample = { atMs: number } & Record<SeriesKey, number | null>;

export interface SeriesInfo {
  key: SeriesKey;
  /** Short, for the legend; `title` says it whole. */
  label: string;
  title: string;
  color: string;
  /** Dashed: a derived age rather than a measured round trip. */
  dashed: boolean;
}

/** The plotted series in drawing order, with the legend's words and colours (one source for both). */
export const SERIES: readonly SeriesInfo[] = [
  { key: 'pingRttMs', label: 'ping RTT', title: 'round trip of the app-level pings (one a second)', color: '#38bdf8', dashed: false },
  { key: 'teleopRttMs', label: 'teleop RTT', title: 'round trip of the teleop commands while driving: sent -> applied by the control loop -> echo', color: '#f472b6', dashed: false },
  { key: 'poseAgeMs', label: 'pose age', title: 'how old the pose on screen is: now - its publish time (wall_us, translated with the clock offset)', color: '#34d399', dashed: true },
  { key: 'scanAgeMs', label: 'scan age', title: 'how old the laser scan on screen is (10 Hz: up to 100 ms more than the pose)', color: '#fbbf24', dashed: true },
];

interface Measurement {
  valueMs: number;
  atMs: number;
}

export class LinkMonitor {
  readonly offset = new ClockOffset();
  /** Some pong carried the server's wall clock: ages are translated, not taken as in sync. */
  offsetMeasured = false;
  private ping: Measurement | null = null;
  private teleop: Measurement | null = null;
  private poseWallUs: number | null = null;
  private scanWallUs: number | null = null;
  private samples: LinkSample[] = [];
  private byteMarks: { atMs: number; total: number }[] = [];

  /** A pong to a ping sent at `sentMs`, received at `receivedMs` (local wall ms). */
  onPong(sentMs: number, receivedMs: number, serverWallUs: number | undefined): void {
    this.ping = { valueMs: receivedMs - sentMs, atMs: receivedMs };
    if (serverWallUs !== undefined) {
      this.offset.add(sentMs, receivedMs, serverWallUs);
      this.offsetMeasured = true;
    }
  }

  /** A teleop command's echo: its round trip (send -> applied by the control loop -> ack). */
  onTeleopEcho(rttMs: number, atMs: number): void {
    if (Number.isFinite(rttMs) && rttMs >= 0) this.teleop = { valueMs: rttMs, atMs };
  }

  /** The pose now on screen was published at `wallUs` (server clock). */
  onPose(wallUs: number | undefined): void {
    if (wallUs !== undefined && wallUs > 0) this.poseWallUs = wallUs;
  }

  /** The scan now on screen was published at `wallUs`. */
  onScan(wallUs: number | undefined): void {
    if (wallUs !== undefined && wallUs > 0) this.scanWallUs = wallUs;
  }

  /** The stream closed: its round trips say nothing about the next connection. */
  disconnected(): void {
    this.ping = null;
    this.teleop = null;
  }

  /** The offset used now (fastest recent pong); null while no pong carried `wall_us`. */
  currentOffset(nowMs: number): OffsetEstimate | null {
    return this.offset.best(nowMs);
  }

  /** Age (ms) at `nowMs` of a frame published at `wallUs`, with the current offset. */
  ageMs(wallUs: number, nowMs: number): number {
    return frameAgeMs(wallUs, nowMs, this.currentOffset(nowMs));
  }

  /** Bytes received per second over the last second; null until two counts are a second apart. */
  bytesPerSecond(): number | null {
    const first = this.byteMarks[0];
    const last = this.byteMarks[this.byteMarks.length - 1];
    if (!first || !last || last.atMs - first.atMs < RATE_WINDOW_MS / 2) return null;
    return ((last.total - first.total) * 1000) / (last.atMs - first.atMs);
  }

  /**
   * Takes one sample at `nowMs` (local wall ms); `totalBytes` is every byte received so far. The
   * ages keep growing while nothing arrives (that is how old the picture on screen is) until the
   * stream is known to be down (`linkUp` false): then the banner says so and the plot has a gap.
   */
  sample(nowMs: number, totalBytes: number, linkUp = true): LinkSample {
    const fresh = (m: Measurement | null, maxAgeMs: number) => (m && nowMs - m.atMs <= maxAgeMs ? m.valueMs : null);
    const s: LinkSample = {
      atMs: nowMs,
      pingRttMs: fresh(this.ping, PING_FRESH_MS),
      teleopRttMs: fresh(this.teleop, TELEOP_FRESH_MS),
      poseAgeMs: this.poseWallUs === null || !linkUp ? null : this.ageMs(this.poseWallUs, nowMs),
      scanAgeMs: this.scanWallUs === null || !linkUp ? null : this.ageMs(this.scanWallUs, nowMs),
    };
    this.samples.push(s);
    const oldest = nowMs - PLOT_WINDOW_MS;
    while (this.samples.length && this.samples[0]!.atMs < oldest) this.samples.shift();
    this.byteMarks.push({ atMs: nowMs, total: totalBytes });
    while (this.byteMarks.length > 2 && this.byteMarks[1]!.atMs <= nowMs - RATE_WINDOW_MS) this.byteMarks.shift();
    return s;
  }

  /** The history, oldest first. */
  history(): readonly LinkSample[] {
    return this.samples;
  }

  /** The newest sample, or null before the first. */
  latest(): LinkSample | null {
    return this.samples[this.samples.length - 1] ?? null;
  }
}

/**
 * The top of the plot's ms axis: the smallest of 50, 100, 200, 500, 1000, 2000 at or above the
 * largest value, so the ticks are round; at most 2000 (longer is drawn clipped at the top, so one
 * outage does not flatten the minute that follows it).
 */
export function plotScaleMs(maxValueMs: number): number {
  for (const top of [50, 100, 200, 500, 1000, 2000]) if (maxValueMs <= top) return top;
  return 2000;
}

/**
 * What the plot's axis must hold: the 95th percentile of every value in `samples` (0 when none).
 * Not the largest: the ages growing through a stall (2 s before the stream is dropped) would
 * flatten the rest of the minute; they are drawn clipped at the top instead.
 */
export function scaleValue(samples: readonly LinkSample[]): number {
  const values: number[] = [];
  for (const s of samples) for (const { key } of SERIES) if (s[key] !== null) values.push(s[key]!);
  if (!values.length) return 0;
  values.sort((a, b) => a - b);
  return values[Math.min(values.length - 1, Math.floor(values.length * 0.95))]!;
}

/** "3.2 ms", "148 ms", "1.24 s": a duration as the Link card shows it. */
export function msText(ms: number | null | undefined): string {
  if (ms === null || ms === undefined || !Number.isFinite(ms)) return '–';
  if (Math.abs(ms) >= 1000) return `${(ms / 1000).toFixed(2)} s`;
  return `${ms.toFixed(Math.abs(ms) < 10 ? 1 : 0)} ms`;
}

/** "812 B/s", "41.3 kB/s", "1.20 MB/s". */
export function rateText(bytesPerSecond: number | null): string {
  if (bytesPerSecond === null || !Number.isFinite(bytesPerSecond)) return '–';
  if (bytesPerSecond < 1000) return `${bytesPerSecond.toFixed(0)} B/s`;
  if (bytesPerSecond < 1e6) return `${(bytesPerSecond / 1000).toFixed(1)} kB/s`;
  return `${(bytesPerSecond / 1e6).toFixed(2)} MB/s`;
}
