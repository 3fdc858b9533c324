import { describe, expect, it } from 'vitest';
import { LinkMonitor, msText, PLOT_WINDOW_MS, plotScaleMs, rateText, SAMPLE_PERIOD_MS, scaleValue, SERIES } from '../src/link';
import type { LinkSample } from '../src/link';
import { axisLabel, gridValues, plotBox, seriesLines } from '../src/link_plot';

describe('LinkMonitor', () => {
  it('samples round trips while fresh, and ages that grow while nothing arrives', () => {
    const m = new LinkMonitor();
    m.onPong(1000, 1004, undefined);
    m.onPose(995 * 1000);
    m.onScan(950 * 1000);
    m.onTeleopEcho(21, 1004);
    let s = m.sample(1010, 0);
    expect(s).toEqual({ atMs: 1010, pingRttMs: 4, teleopRttMs: 21, poseAgeMs: 15, scanAgeMs: 60 });
    // 2 s later: the teleop echo is stale (not driving), the ping not yet; the pose is 2 s older.
    s = m.sample(3010, 0);
    expect(s.teleopRttMs).toBeNull();
    expect(s.pingRttMs).toBe(4);
    expect(s.poseAgeMs).toBe(2015);
    m.disconnected();
    expect(m.sample(3260, 0).pingRttMs).toBeNull();
    // The stream is down: the banner says so, the ages pause.
    expect(m.sample(3510, 0, false).poseAgeMs).toBeNull();
  });

  it('translates ages with the offset once a pong carries the server wall clock', () => {
    const m = new LinkMonitor();
    // The server's clock is 1 s ahead of the page's.
    m.onPong(1000, 1010, (1005 + 1000) * 1000);
    expect(m.offsetMeasured).toBe(true);
    m.onPose((1008 + 1000) * 1000); // published at local 1008
    expect(m.sample(1012, 0).poseAgeMs).toBeCloseTo(4);
  });

  it('keeps a 60 s history', () => {
    const m = new LinkMonitor();
    for (let t = 0; t <= 2 * PLOT_WINDOW_MS; t += SAMPLE_PERIOD_MS) m.sample(t, 0);
    expect(m.history().length).toBe(PLOT_WINDOW_MS / SAMPLE_PERIOD_MS + 1);
    expect(m.history()[0]!.atMs).toBe(PLOT_WINDOW_MS);
  });

  it('measures bytes per second over about a second', () => {
    const m = new LinkMonitor();
    m.sample(0, 0);
    expect(m.bytesPerSecond()).toBeNull();
    for (let t = 250; t <= 3000; t += 250) m.sample(t, t * 40); // 40 kB/s
    expect(m.bytesPerSecond()).toBeCloseTo(40_000);
  });
});

describe('the plot', () => {
  const sample = (atMs: number, pingRttMs: number | null): LinkSample => ({ atMs, pingRttMs, teleopRttMs: null, poseAgeMs: null, scanAgeMs: null });

  it('picks a round axis top, at most 2 s', () => {
    expect([0, 3, 50, 51, 180, 320, 999, 1500, 9000].map(plotScaleMs)).toEqual([50, 50, 50, 100, 200, 500, 1000, 2000, 2000]);
    expect(scaleValue([sample(0, 12), { ...sample(1, null), scanAgeMs: 140 }])).toBe(140);
    // A few seconds of outage in a minute do not set the scale.
    const minute = Array.from({ length: 240 }, (_, i) => ({ ...sample(i * 250, 300), poseAgeMs: i >= 230 ? 2500 : 150 }));
    expect(plotScaleMs(scaleValue(minute))).toBe(500);
    expect(scaleValue([])).toBe(0);
    expect(gridValues(200)).toEqual([0, 50, 100, 150, 200]);
    expect([0, 50, 500, 1000, 2000].map(axisLabel)).toEqual(['0 ms', '50 ms', '500 ms', '1 s', '2 s']);
  });

  it('places the minute left to right and 0 ms at the bottom; breaks at gaps; clips at the top', () => {
    const box = plotBox(344, 130);
    expect(box).toEqual({ left: 44, top: 10, width: 292, height: 102 });
    const now = 100_000;
    const samples = [sample(now - PLOT_WINDOW_MS, 0), sample(now - PLOT_WINDOW_MS + 250, 100), sample(now - 250, 50), sample(now, 400)];
    const lines = seriesLines(samples, 'pingRttMs', now, box, 100);
    // The third sample is 50 s after the second: a new line.
    expect(lines.length).toBe(2);
    expect(lines[0]![0]).toEqual([44, 112]);
    expect(lines[0]![1]![1]).toBe(10);
    expect(lines[1]![1]).toEqual([336, 10]); // 400 ms drawn on the top edge of a 100 ms axis
    expect(seriesLines([sample(now, null)], 'pingRttMs', now, box, 100)).toEqual([]);
  });

  it('has one colour and label per series', () => {
    expect(new Set(SERIES.map((s) => s.color)).size).toBe(SERIES.length);
    expect(SERIES.map((s) => s.key)).toEqual(['pingRttMs', 'teleopRttMs', 'poseAgeMs', 'scanAgeMs']);
  });
});

describe('numbers as the card shows them', () => {
  it('formats durations and rates', () => {
    expect([null, 3.21, 148.4, 1240].map(msText)).toEqual(['–', '3.2 ms', '148 ms', '1.24 s']);
    expect([null, 812, 41_300, 1_200_000].map(rateText)).toEqual(['–', '812 B/s', '41.3 kB/s', '1.20 MB/s']);
  });
});
