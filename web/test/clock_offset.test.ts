import { describe, expect, it } from 'vitest';
import { ClockOffset, frameAgeMs, OFFSET_WINDOW_MS } from '../src/clock_offset';

describe('the server clock seen from the page', () => {
  it('takes the midpoint of the ping: symmetric delays cancel out', () => {
    const c = new ClockOffset();
    // The server is 500 ms ahead; 150 ms each way.
    c.add(10_000, 10_300, (10_150 + 500) * 1000);
    expect(c.best(10_300)).toEqual({ offsetMs: 500, rttMs: 300, atMs: 10_300 });
  });

  it('keeps the fastest pong of the window, and forgets old ones', () => {
    const c = new ClockOffset();
    c.add(0, 10, 5_000); // offset 0, rtt 10
    c.add(1000, 1100, 1_080_000); // answered late in a queue: offset 30, rtt 100
    expect(c.best(2000)!.offsetMs).toBe(0);
    expect(c.best(OFFSET_WINDOW_MS + 500)!.offsetMs).toBe(30);
    expect(c.best(OFFSET_WINDOW_MS + 2000)).toBeNull();
  });

  it('ignores pongs without a usable wall clock', () => {
    const c = new ClockOffset();
    c.add(0, 10, 0);
    c.add(20, 10, 5000); // received before sent
    c.add(0, 10, Number.NaN);
    expect(c.best(20)).toBeNull();
  });

  it('translates a frame stamp into its age here', () => {
    // Published at server 2000 ms, server 500 ms ahead: at local 1600 it is 100 ms old.
    expect(frameAgeMs(2_000_000, 1600, { offsetMs: 500, rttMs: 1, atMs: 0 })).toBeCloseTo(100);
    // No estimate: the clocks are taken as in sync.
    expect(frameAgeMs(2_000_000, 2030, null)).toBeCloseTo(30);
  });
});
