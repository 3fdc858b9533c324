import { describe, expect, it } from 'vitest';
import { Poller } from '../src/poller';
import type { PollTimers } from '../src/poller';

/** A manual clock: timers fire when advance() passes them. */
class FakeTimers implements PollTimers {
  private t = 0;
  private nextId = 1;
  private readonly pending = new Map<number, { at: number; fn: () => void }>();

  now(): number {
    return this.t;
  }

  setTimeout(fn: () => void, ms: number): unknown {
    const id = this.nextId++;
    this.pending.set(id, { at: this.t + ms, fn });
    return id;
  }

  clearTimeout(handle: unknown): void {
    this.pending.delete(handle as number);
  }

  /** Moves the clock, firing due timers in order (and letting their promises settle). */
  async advance(ms: number): Promise<void> {
    const end = this.t + ms;
    for (;;) {
      let due: [number, { at: number; fn: () => void }] | null = null;
      for (const entry of this.pending) if (entry[1].at <= end && (!due || entry[1].at < due[1].at)) due = entry;
      if (!due) break;
      this.pending.delete(due[0]);
      this.t = Math.max(this.t, due[1].at);
      due[1].fn();
      await flush();
    }
    this.t = end;
    await flush();
  }
}

const flush = async () => {
  for (let i = 0; i < 5; i++) await Promise.resolve();
};

/** A poller whose runs are recorded at the fake time they start; `hold` keeps a run in flight. */
function setup(periodMs = 2000, minGapMs = 500) {
  const timers = new FakeTimers();
  const starts: number[] = [];
  let release: (() => void) | null = null;
  const control = { hold: false };
  const poller = new Poller(
    () => {
      starts.push(timers.now());
      if (!control.hold) return Promise.resolve();
      return new Promise<void>((resolve) => (release = resolve));
    },
    { periodMs, minGapMs },
    timers,
  );
  const finish = async () => {
    release?.();
    release = null;
    await flush();
  };
  return { timers, starts, poller, control, finish };
}

describe('Poller', () => {
  it('runs at once on start, then once a period, and stops', async () => {
    const { timers, starts, poller } = setup();
    poller.start();
    await timers.advance(0);
    await timers.advance(6500);
    expect(starts).toEqual([0, 2000, 4000, 6000]);
    poller.stop();
    await timers.advance(10_000);
    expect(starts.length).toBe(4);
    expect(poller.runs).toBe(4);
  });

  it('a poke runs at once when the gap allows, and the period counts from it', async () => {
    const { timers, starts, poller } = setup();
    poller.start();
    await timers.advance(1200);
    poller.poke();
    await timers.advance(0);
    await timers.advance(2500);
    expect(starts).toEqual([0, 1200, 3200]);
  });

  it('pokes in a burst run once, no sooner than the minimum gap after the last run', async () => {
    const { timers, starts, poller } = setup();
    poller.start();
    await timers.advance(100);
    for (let i = 0; i < 15; i++) poller.poke();
    await timers.advance(1000);
    expect(starts).toEqual([0, 500]);
  });

  it('one request in flight at a time: a poke during a run runs once after it', async () => {
    const { timers, starts, poller, control, finish } = setup();
    control.hold = true;
    poller.start();
    await timers.advance(0);
    poller.poke();
    poller.poke();
    await timers.advance(3000);
    expect(starts).toEqual([0]);
    control.hold = false;
    await finish();
    await timers.advance(0);
    expect(starts).toEqual([0, 3000]);
    await timers.advance(2000);
    expect(starts).toEqual([0, 3000, 5000]);
  });

  it('fresh() (the state came with a POST reply) puts the next run a whole period away', async () => {
    const { timers, starts, poller } = setup();
    poller.start();
    await timers.advance(1500);
    poller.fresh();
    await timers.advance(1900);
    expect(starts).toEqual([0]);
    await timers.advance(100);
    expect(starts).toEqual([0, 3500]);
  });

  it('does nothing before start or after stop, and a run ending after stop schedules nothing', async () => {
    const { timers, starts, poller, control, finish } = setup();
    poller.poke();
    poller.fresh();
    await timers.advance(5000);
    expect(starts).toEqual([]);
    control.hold = true;
    poller.start();
    await timers.advance(0);
    poller.stop();
    await finish();
    await timers.advance(10_000);
    expect(starts).toEqual([5000]);
    expect(poller.active).toBe(false);
  });

  it('a failing run does not stop polling', async () => {
    const timers = new FakeTimers();
    let runs = 0;
    const poller = new Poller(() => {
      runs++;
      return Promise.reject(new Error('unreachable'));
    }, { periodMs: 1000, minGapMs: 100 }, timers);
    poller.start();
    await timers.advance(2500);
    expect(runs).toBe(3);
  });
});
