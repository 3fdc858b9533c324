import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import type { CloudChunk } from '../src/frames';
import { newestSweep, sweepErrorText, sweepProgress, SweepTracker } from '../src/sweeps';
import type { SweepInfo } from '../src/sweeps';

/** A chunk of `count` points at z = 1 (x = the point's index within the sweep). */
function chunk(sweepId: number, first: number, count: number, scansDone: number, opts: { last?: boolean; scansTotal?: number } = {}): CloudChunk {
  const points = new Float32Array(count * 4);
  for (let i = 0; i < count; i++) points.set([first + i, 0, 1, 0.5], 4 * i);
  return { sweepId, first, count, last: opts.last ?? false, scansDone, scansTotal: opts.scansTotal ?? 4, points };
}

function info(id: number, status: SweepInfo['status'], scansDone: number, points: number, scans = 4): SweepInfo {
  return { id, status, points, mode: { period_s: 10, step_deg: 1, scans }, scans_done: scansDone, started_t: 1 };
}

describe('sweepProgress', () => {
  it('is scans done over scans in total, clamped, and 1 once done', () => {
    expect(sweepProgress(0, 24, 'running')).toBe(0);
    expect(sweepProgress(6, 24, 'running')).toBe(0.25);
    expect(sweepProgress(30, 24, 'running')).toBe(1);
    expect(sweepProgress(5, 0, 'running')).toBe(0); // total not known yet
    expect(sweepProgress(0, 0, 'done')).toBe(1);
    expect(sweepProgress(3, 24, 'failed')).toBe(0.125); // the bar stops where it failed
    expect(sweepProgress(NaN, 24, null)).toBe(0);
  });
});

describe('SweepTracker', () => {
  it('appends chunks in order and reports progress from scans_done / scans_total', () => {
    const t = new SweepTracker();
    expect(t.onChunk(chunk(1, 0, 100, 1)).reset).toBe(true);
    expect(t.progress).toBe(0.25);
    t.onChunk(chunk(1, 100, 50, 2));
    expect(t.cloud.count).toBe(150);
    expect(t.nextPoint).toBe(150);
    expect(t.incomplete).toBe(false);
    expect(t.progress).toBe(0.5);
    expect(t.cloud.positions[3 * 149]).toBe(149);
  });

  it('reserves scans_total x the first chunk up front', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 700, 1, { scansTotal: 80 }));
    expect(t.cloud.capacity).toBeGreaterThanOrEqual(56000);
    const generation = t.cloud.generation;
    for (let s = 1; s < 80; s++) t.onChunk(chunk(1, 700 * s, 700, s + 1, { scansTotal: 80 }));
    expect(t.cloud.count).toBe(56000);
    expect(t.cloud.generation).toBe(generation); // no reallocation during the sweep
  });

  it('skips a chunk seen twice and marks a missed chunk as a gap', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 10, 1));
    t.onChunk(chunk(1, 0, 10, 1)); // again
    expect(t.cloud.count).toBe(10);
    t.onChunk(chunk(1, 5, 10, 2)); // overlaps 5 points
    expect(t.cloud.count).toBe(15);
    expect(t.cloud.positions[3 * 14]).toBe(14);
    t.onChunk(chunk(1, 30, 10, 4)); // 15..29 were dropped
    expect(t.incomplete).toBe(true);
    expect(t.cloud.count).toBe(25);
    expect(t.nextPoint).toBe(40);
  });

  it('resets when a chunk of another sweep arrives', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 10, 4, { last: true }));
    const change = t.onChunk(chunk(2, 0, 3, 1));
    expect(change.reset).toBe(true);
    expect(t.id).toBe(2);
    expect(t.status).toBe('running');
    expect(t.cloud.count).toBe(3);
    expect(t.scanned).toBe(false);
    expect(t.progress).toBe(0.25);
  });

  it('takes the last chunk as scanned, the sweep done only from REST or the event', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 10, 3));
    const last = t.onChunk(chunk(1, 10, 10, 4, { last: true }));
    expect(last.finished).toBe(false);
    expect(t.status).toBe('running');
    expect(t.scanned).toBe(true);
    expect(t.progress).toBe(1);
    // The server still runs IPaBD: a poll says running.
    expect(t.onInfo(info(1, 'running', 4, 20)).finished).toBe(false);
    const done = t.onInfo(info(1, 'done', 4, 20));
    expect(done.finished).toBe(true);
    expect(t.status).toBe('done');
    expect(t.needsFullCloud).toBe(false);
    expect(t.onEvent({ id: 1, status: 'done' }).finished).toBe(false); // reported once
  });

  it('a poll that lags the frames does not move the bar back; one ahead moves it on', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 10, 3));
    t.onInfo(info(1, 'running', 1, 10));
    expect(t.scansDone).toBe(3);
    t.onInfo(info(1, 'running', 4, 40)); // frames were dropped: the poll is the fallback
    expect(t.scansDone).toBe(4);
    expect(t.progress).toBe(1);
  });

  it('learns scans_total from the poll when no frame came', () => {
    const t = new SweepTracker();
    t.follow(7);
    expect(t.progress).toBe(0);
    t.onInfo(info(7, 'running', 6, 600, 24));
    expect(t.scansTotal).toBe(24);
    expect(t.progress).toBe(0.25);
  });

  it('ignores polls of other sweeps', () => {
    const t = new SweepTracker();
    t.follow(3);
    expect(t.onInfo(info(2, 'done', 4, 99)).finished).toBe(false);
    expect(t.status).toBe('running');
    expect(t.info).toBeNull();
  });

  it('asks for the whole cloud when done with a gap or fewer points than the server has', () => {
    const gap = new SweepTracker();
    gap.onChunk(chunk(1, 0, 10, 1));
    gap.onChunk(chunk(1, 20, 10, 3, { last: true }));
    expect(gap.needsFullCloud).toBe(false); // not done yet
    gap.onEvent({ id: 1, status: 'done' });
    expect(gap.needsFullCloud).toBe(true);

    const short = new SweepTracker();
    short.onChunk(chunk(1, 0, 10, 4, { last: true }));
    short.onInfo(info(1, 'done', 4, 12)); // the server counts 12
    expect(short.needsFullCloud).toBe(true);

    // The whole cloud (one frame, last set) replaces the points.
    expect(gap.loadFull(chunk(1, 0, 30, 4, { last: true }))).toBe(true);
    expect(gap.cloud.count).toBe(30);
    expect(gap.incomplete).toBe(false);
    expect(gap.needsFullCloud).toBe(false);
    gap.onChunk(chunk(1, 30, 5, 4)); // a late chunk adds nothing to a whole cloud
    expect(gap.cloud.count).toBe(30);
    expect(gap.loadFull(chunk(2, 0, 5, 4, { last: true }))).toBe(false); // another sweep's
  });

  it('follows a sweep from an event or a POST reply without resetting one it tracks', () => {
    const t = new SweepTracker();
    expect(t.onEvent({ id: 5, status: 'running', scans: 24 }).reset).toBe(true);
    t.onChunk(chunk(5, 0, 10, 1));
    expect(t.follow(5).reset).toBe(false); // the POST reply came after the first chunk
    expect(t.cloud.count).toBe(10);
    expect(t.onEvent({ id: 5, status: 'failed' }).finished).toBe(true);
    expect(t.status).toBe('failed');
    expect(t.onEvent({ id: 'x', status: 'running' }).reset).toBe(false);
    expect(t.onEvent({ id: 6, status: 'weird' }).reset).toBe(false);
  });

  it('show() tracks a listed sweep; a done one starts without points', () => {
    const t = new SweepTracker();
    t.onChunk(chunk(1, 0, 10, 1));
    const change = t.show(info(9, 'done', 24, 5000, 24));
    expect(change).toEqual({ reset: true, finished: false });
    expect(t.cloud.count).toBe(0);
    expect(t.progress).toBe(1);
    expect(t.needsFullCloud).toBe(true);
  });
});

describe('sweep list and errors', () => {
  it('finds the newest sweep with a status', () => {
    const list = [info(3, 'done', 4, 1), info(5, 'failed', 1, 0), info(4, 'done', 4, 1)];
    expect(newestSweep(list)?.id).toBe(5);
    expect(newestSweep(list, (s) => s.status === 'done')?.id).toBe(4);
    expect(newestSweep(list, (s) => s.status === 'running')).toBeNull();
  });

  it('explains the refusals', () => {
    expect(sweepErrorText(new ApiError(409, 'sweep_running', '3D sweep 4 is running'))).toMatch(/already running.*3D sweep 4 is running/);
    expect(sweepErrorText(new ApiError(403, 'forbidden', 'operator role needed'))).toMatch(/operator role/);
    expect(sweepErrorText(new ApiError(400, 'invalid_mode', 'period_s must be 10 or 42'))).toMatch(/period_s must be 10 or 42/);
    expect(sweepErrorText(new ApiError(404, 'not_found', 'no such endpoint'))).toMatch(/no 3D sweeps/);
    expect(sweepErrorText(new ApiError(500, 'internal', 'boom'))).toBe('The sweep was refused: boom (internal)');
    expect(sweepErrorText(new Error('offline'))).toBe('The sweep request failed: offline');
  });
});
