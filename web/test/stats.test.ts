import { describe, expect, it } from 'vitest';
import { backoffDelayMs, StreamStats } from '../src/stats';
import { applyDeadzone, keysToAxes, padToAxes } from '../src/teleop';

describe('StreamStats', () => {
  it('counts frames per second per topic', () => {
    const s = new StreamStats(1000);
    for (let i = 0; i < 50; i++) s.record('pose', i + 1, undefined, 1000 + i * 20);
    s.tick(2000);
    expect(s.get('pose')!.rateHz).toBeCloseTo(50, 0);
    s.tick(3500);
    expect(s.get('pose')!.rateHz).toBe(0);
  });

  it('counts seq gaps as dropped frames and restarts on a lower seq', () => {
    const s = new StreamStats();
    [1, 2, 5, 6, 10].forEach((seq, i) => s.record('scan', seq, undefined, i));
    expect(s.get('scan')!.gaps).toBe(5);
    s.record('scan', 1, undefined, 10); // server restarted
    s.record('scan', 2, undefined, 11);
    expect(s.get('scan')!.gaps).toBe(5);
    s.resetSequences();
    s.record('scan', 50, undefined, 12);
    expect(s.totalGaps()).toBe(5);
  });

  it('measures publish-to-receipt latency from wall_us', () => {
    const s = new StreamStats();
    s.record('pose', 1, 1_000_000_000, 1_000_010);
    expect(s.get('pose')!.latencyMs).toBeCloseTo(10);
  });

  it('backs off exponentially up to the cap', () => {
    expect([0, 1, 2, 3, 4, 10].map((a) => backoffDelayMs(a))).toEqual([250, 500, 1000, 2000, 2000, 2000]);
  });
});

describe('teleop mapping', () => {
  it('maps held keys to forward / turn', () => {
    expect(keysToAxes(new Set(['w']))).toEqual({ forward: 1, turn: 0 });
    expect(keysToAxes(new Set(['arrowdown', 'd']))).toEqual({ forward: -1, turn: -1 });
    expect(keysToAxes(new Set(['w', 's', 'a']))).toEqual({ forward: 0, turn: 1 });
  });

  it('maps the joystick knob (screen y down) and clips to the unit disc', () => {
    expect(padToAxes(0, -50, 50)).toEqual({ forward: 1, turn: -0 });
    const a = padToAxes(100, 100, 50);
    expect(Math.hypot(a.forward, a.turn)).toBeCloseTo(1);
    expect(a.forward).toBeLessThan(0);
    expect(a.turn).toBeLessThan(0);
  });

  it('applies a dead zone', () => {
    expect(applyDeadzone(0.1)).toBe(0);
    expect(applyDeadzone(1)).toBeCloseTo(1);
    expect(applyDeadzone(-1)).toBeCloseTo(-1);
  });
});
