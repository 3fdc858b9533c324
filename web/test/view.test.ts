import { describe, expect, it } from 'vitest';
import { boundsOf, MAX_SCALE, ViewTransform, wheelZoomFactor } from '../src/map/view_transform';

describe('ViewTransform', () => {
  it('maps y up in the world to y down on screen and back', () => {
    const v = new ViewTransform(50, 100, 200);
    expect(v.toScreen(1, 1)).toEqual([150, 150]);
    const [x, y] = v.toWorld(150, 150);
    expect(x).toBeCloseTo(1);
    expect(y).toBeCloseTo(1);
  });

  it('keeps the point under the cursor fixed when zooming', () => {
    const v = new ViewTransform(40, 10, 300);
    const cursor: [number, number] = [237, 81];
    const before = v.toWorld(...cursor);
    v.zoomAbout(cursor[0], cursor[1], 2.5);
    expect(v.scale).toBeCloseTo(100);
    const after = v.toWorld(...cursor);
    expect(after[0]).toBeCloseTo(before[0], 9);
    expect(after[1]).toBeCloseTo(before[1], 9);
  });

  it('clamps the zoom', () => {
    const v = new ViewTransform(1000);
    v.zoomAbout(0, 0, 100);
    expect(v.scale).toBe(MAX_SCALE);
  });

  it('pans in screen pixels', () => {
    const v = new ViewTransform(20, 0, 0);
    v.panBy(40, -20);
    expect(v.toWorld(40, -20)).toEqual([0, 0]);
  });

  it('fits bounds centred with the limiting axis filling the viewport', () => {
    const v = new ViewTransform();
    v.fit({ minX: -5, minY: 0, maxX: 15, maxY: 10 }, 440, 440, 20);
    expect(v.scale).toBeCloseTo(20); // 400 px for 20 m
    const [cx, cy] = v.toScreen(5, 5);
    expect(cx).toBeCloseTo(220);
    expect(cy).toBeCloseTo(220);
    const [left] = v.toScreen(-5, 0);
    expect(left).toBeCloseTo(20);
  });

  it('gives a canvas matrix that agrees with toScreen', () => {
    const v = new ViewTransform(30, 12, 34);
    const [a, b, c, d, e, f] = v.matrix(2);
    const [x, y] = [1.5, -2];
    expect([a * x + c * y + e, b * x + d * y + f]).toEqual(v.toScreen(x, y).map((s) => 2 * s));
  });
});

describe('helpers', () => {
  it('bounds skip non-finite points', () => {
    expect(boundsOf([[1, 2], [NaN, 0], [-3, 5]])).toEqual({ minX: -3, minY: 2, maxX: 1, maxY: 5 });
    expect(boundsOf([])).toBeNull();
  });

  it('wheel zooms in for negative deltas and out for positive ones', () => {
    expect(wheelZoomFactor(-100)).toBeGreaterThan(1);
    expect(wheelZoomFactor(100)).toBeLessThan(1);
    expect(wheelZoomFactor(100) * wheelZoomFactor(-100)).toBeCloseTo(1);
    expect(wheelZoomFactor(3, 1)).toBeCloseTo(wheelZoomFactor(48, 0));
  });
});
