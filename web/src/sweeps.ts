// 3D sweeps of the tilting laser: the REST bodies, a sweep's progress, and the state of the sweep
// the 3D view shows, merged from three sources that may arrive in any order: the `cloud` topic's
// chunks, GET /api/v1/sweeps/{id} polls (the fallback when frames are dropped) and `sweep` events.
// Pure (no DOM, no fetch), so it is unit-tested.

import { ApiError, errorText } from './apierror';
import { CloudBuffer, sweepCapacityHint } from './cloud';
import type { CloudChunk } from './frames';

export type SweepStatus = 'running' | 'done' | 'failed';

/** Tilt periods (s) and scan steps (deg) the server accepts. */
export const SWEEP_PERIODS_S = [10, 42] as const;
export const SWEEP_STEPS_DEG = [1, 0.5, 0.25] as const;

export interface SweepRequest {
  period_s?: (typeof SWEEP_PERIODS_S)[number];
  step_deg?: (typeof SWEEP_STEPS_DEG)[number];
}

export interface SweepInfo {
  id: number;
  status: SweepStatus;
  /** Points so far (all of them once done). */
  points: number;
  /** `scans`: the sweep's number of scans. */
  mode: { period_s: number; step_deg: number; scans: number };
  scans_done: number;
  /** Robot clock (s). */
  started_t: number;
  ended_t?: number;
  reason?: string;
}

/** Fraction 0..1 of a sweep done: scans done over scans in total; 1 once done. */
export function sweepProgress(scansDone: number, scansTotal: number, status: SweepStatus | null): number {
  if (status === 'done') return 1;
  if (!(scansTotal > 0) || !(scansDone > 0)) return 0;
  return Math.min(1, scansDone / scansTotal);
}

/** The newest sweep (highest id) that `accept` accepts, or null. */
export function newestSweep(sweeps: readonly SweepInfo[], accept: (s: SweepInfo) => boolean = () => true): SweepInfo | null {
  let best: SweepInfo | null = null;
  for (const s of sweeps) if (accept(s) && (!best || s.id > best.id)) best = s;
  return best;
}

/** What a refused POST /api/v1/sweeps means for the user. */
export function sweepErrorText(error: unknown): string {
  if (error instanceof ApiError) {
    switch (error.code) {
      case 'sweep_running':
        return `A sweep is already running: wait until it ends. (${error.message})`;
      case 'forbidden':
        return 'This token may not start a sweep (the operator role is needed).';
      case 'invalid_mode':
        return `The server does not accept this mode: ${error.message}`;
      case 'estop_engaged':
        return 'The e-stop is engaged: release it first.';
      default:
        if (error.status === 404) return 'This server has no 3D sweeps (the tilting laser is not available).';
        return `The sweep was refused: ${error.describe()}`;
    }
  }
  return `The sweep request failed: ${errorText(error)}`;
}

/** What a change did to the tracked sweep. */
export interface SweepChange {
  /** Another sweep is now tracked: its buffer was emptied. */
  reset: boolean;
  /** The tracked sweep just ended (done or failed); reported once per sweep. */
  finished: boolean;
}

/**
 * The sweep shown in the 3D view and its points. Chunks are appended in order; one that starts
 * past the points held (a dropped frame, or a sweep joined midway) marks the cloud incomplete, and
 * an overlap (a chunk seen twice) is skipped. The last chunk only means the laser is through
 * (`scanned`): the server runs IPaBD and stores the cloud before it calls the sweep done, and only
 * REST or the `sweep` event say so. Once done, an incomplete cloud is replaced by the server's
 * whole cloud (`needsFullCloud`, then `loadFull`).
 */
export class SweepTracker {
  readonly cloud = new CloudBuffer();
  id: number | null = null;
  status: SweepStatus | null = null;
  scansDone = 0;
  scansTotal = 0;
  /** The last chunk arrived: every scan is in (the server may still be processing). */
  scanned = false;
  /** The sweep's point index the next chunk should start at. */
  nextPoint = 0;
  /** A chunk was missed: the points held are not the whole cloud. */
  incomplete = false;
  /** The buffer holds the server's whole cloud (GET ...?format=bin): later chunks add nothing. */
  loadedFull = false;
  /** The latest REST view of the sweep. */
  info: SweepInfo | null = null;

  get progress(): number {
    return sweepProgress(this.scanned ? Math.max(this.scansDone, this.scansTotal) : this.scansDone, this.scansTotal, this.status);
  }

  /** Whether the sweep is done and the points held are fewer than the server has. */
  get needsFullCloud(): boolean {
    if (this.status !== 'done' || this.loadedFull) return false;
    return this.incomplete || (this.info !== null && this.nextPoint < this.info.points);
  }

  /** Tracks sweep `id` (a POST reply, a `sweep` event) unless it already is. */
  follow(id: number, status: SweepStatus = 'running'): SweepChange {
    if (this.id === id) return { reset: false, finished: false };
    this.begin(id, status);
    return { reset: true, finished: false };
  }

  /** Tracks a listed sweep (opening the page, choosing one): its points come from loadFull. */
  show(info: SweepInfo): SweepChange {
    const reset = this.id !== info.id;
    if (reset) this.begin(info.id, info.status);
    const change = this.onInfo(info);
    return { reset, finished: change.finished && !reset };
  }

  /** A `cloud` chunk: a chunk of another sweep means that sweep started, so it is tracked instead. */
  onChunk(chunk: CloudChunk): SweepChange {
    let reset = false;
    if (chunk.sweepId !== this.id) {
      this.begin(chunk.sweepId, 'running');
      reset = true;
    }
    if (chunk.scansTotal > 0) this.scansTotal = chunk.scansTotal;
    this.scansDone = Math.max(this.scansDone, chunk.scansDone);
    if (!this.loadedFull) {
      if (this.cloud.count === 0) this.cloud.reserve(sweepCapacityHint(chunk.scansTotal, chunk.count));
      if (chunk.first > this.nextPoint) this.incomplete = true;
      const alreadyHeld = Math.max(0, this.nextPoint - chunk.first);
      if (alreadyHeld < chunk.count) this.cloud.append(chunk.points, chunk.count - alreadyHeld, alreadyHeld);
      this.nextPoint = Math.max(this.nextPoint, chunk.first + chunk.count);
    }
    if (chunk.last) this.scanned = true;
    return { reset, finished: false };
  }

  /** A GET /sweeps/{id} reply; other sweeps' replies are ignored. */
  onInfo(info: SweepInfo): SweepChange {
    if (info.id !== this.id) return { reset: false, finished: false };
    this.info = info;
    this.scansDone = Math.max(this.scansDone, info.scans_done ?? 0);
    if (!(this.scansTotal > 0) && info.mode?.scans > 0) this.scansTotal = info.mode.scans;
    const finished = info.status !== 'running' ? this.end(info.status) : false;
    return { reset: false, finished };
  }

  /** A `sweep` event (`detail` {id, status}): a new running sweep is tracked, an end is noted. */
  onEvent(detail: { id?: unknown; status?: unknown; [key: string]: unknown }): SweepChange {
    const id = Number(detail.id);
    const status = detail.status;
    if (!Number.isInteger(id) || (status !== 'running' && status !== 'done' && status !== 'failed')) {
      return { reset: false, finished: false };
    }
    if (status === 'running') return this.follow(id);
    if (id !== this.id) return { reset: false, finished: false };
    return { reset: false, finished: this.end(status) };
  }

  /** The whole cloud of the tracked sweep (one frame, ?format=bin); false when it is another sweep's. */
  loadFull(chunk: CloudChunk): boolean {
    if (chunk.sweepId !== this.id) return false;
    this.cloud.clear();
    this.cloud.reserve(chunk.count);
    this.cloud.append(chunk.points, chunk.count);
    this.nextPoint = chunk.first + chunk.count;
    this.incomplete = false;
    this.loadedFull = chunk.last;
    this.scanned ||= chunk.last;
    if (chunk.scansTotal > 0) this.scansTotal = chunk.scansTotal;
    this.scansDone = Math.max(this.scansDone, chunk.scansDone);
    return true;
  }

  private begin(id: number, status: SweepStatus): void {
    this.id = id;
    this.status = status;
    this.scansDone = 0;
    this.scansTotal = 0;
    this.scanned = status !== 'running';
    this.nextPoint = 0;
    this.incomplete = false;
    this.loadedFull = false;
    this.info = null;
    this.cloud.clear();
  }

  /** Marks the end; true when the sweep was running until now. */
  private end(status: 'done' | 'failed'): boolean {
    const wasRunning = this.status === 'running';
    this.status = status;
    if (status === 'done') this.scanned = true;
    return wasRunning;
  }
}
