import { describe, expect, it } from 'vitest';
import {
  CloudBuffer,
  grownCapacity,
  HEIGHT_STOPS,
  heightColor,
  heightLegendGradient,
  MAX_POINTS_PER_SCAN,
  paintFloor,
  snappedHeightRange,
  sweepCapacityHint,
} from '../src/cloud';

/** Points as the cloud frame carries them: x, y, z, intensity. */
function xyzi(...points: [number, number, number][]): Float32Array {
  return Float32Array.from(points.flatMap(([x, y, z]) => [x, y, z, 0.5]));
}

function colorOf(z: number, lowM: number, highM: number): number[] {
  const out = new Uint8Array(3);
  heightColor(z, { lowM, highM }, out, 0);
  return Array.from(out);
}

describe('height colour map', () => {
  it('maps the range ends to the first and last stops and clamps outside', () => {
    expect(colorOf(0, 0, 2)).toEqual([...HEIGHT_STOPS[0]!]);
    expect(colorOf(2, 0, 2)).toEqual([...HEIGHT_STOPS[HEIGHT_STOPS.length - 1]!]);
    expect(colorOf(-5, 0, 2)).toEqual(colorOf(0, 0, 2));
    expect(colorOf(9, 0, 2)).toEqual(colorOf(2, 0, 2));
    expect(colorOf(NaN, 0, 2)).toEqual(colorOf(0, 0, 2));
    expect(colorOf(1, 1, 1)).toEqual(colorOf(0, 0, 2)); // empty range: the low colour
  });

  it('passes through the middle stop and goes from blue (low) to red (high)', () => {
    const stops = HEIGHT_STOPS.length - 1;
    expect(colorOf(2 / stops, 0, 1)).toEqual([...HEIGHT_STOPS[2]!]);
    const [lowR, , lowB] = colorOf(0.1, 0, 2);
    const [highR, , highB] = colorOf(1.9, 0, 2);
    expect(lowB).toBeGreaterThan(lowR!);
    expect(highR).toBeGreaterThan(highB!);
  });

  it('writes at the given offset', () => {
    const out = new Uint8Array(9);
    heightColor(2, { lowM: 0, highM: 2 }, out, 6);
    expect(Array.from(out.subarray(0, 6))).toEqual([0, 0, 0, 0, 0, 0]);
    expect(Array.from(out.subarray(6))).toEqual([...HEIGHT_STOPS[HEIGHT_STOPS.length - 1]!]);
  });

  it('snaps the scale outward to 0.25 m, at least one step wide', () => {
    expect(snappedHeightRange(-0.02, 2.43)).toEqual({ lowM: -0.25, highM: 2.5 });
    expect(snappedHeightRange(0, 1)).toEqual({ lowM: 0, highM: 1 });
    expect(snappedHeightRange(0.5, 0.5)).toEqual({ lowM: 0.5, highM: 0.75 });
  });

  it('gives the legend a CSS gradient from the low to the high colour', () => {
    const css = heightLegendGradient();
    expect(css.startsWith('linear-gradient(to top, ')).toBe(true);
    expect(css).toContain(`rgb(${HEIGHT_STOPS[0]!.join(', ')}) 0%`);
    expect(css).toContain(`rgb(${HEIGHT_STOPS[HEIGHT_STOPS.length - 1]!.join(', ')}) 100%`);
  });
});

describe('capacity', () => {
  it('keeps a capacity that fits and otherwise at least doubles it', () => {
    expect(grownCapacity(4096, 4096)).toBe(4096);
    expect(grownCapacity(4096, 4097)).toBe(8192);
    expect(grownCapacity(4096, 20000)).toBe(20000);
    expect(grownCapacity(0, 10)).toBe(1024);
  });

  it('hints scans_total x the first chunk, capped at 721 points per scan', () => {
    expect(sweepCapacityHint(24, 400)).toBe(9600);
    expect(sweepCapacityHint(320, 5000)).toBe(320 * MAX_POINTS_PER_SCAN);
    expect(sweepCapacityHint(0, 0)).toBe(1);
  });
});

describe('CloudBuffer', () => {
  it('appends points, tracks bounds and colours each by height', () => {
    const cloud = new CloudBuffer(4);
    expect(cloud.append(xyzi([1, 2, 0], [3, -1, 2]), 2)).toBe(2);
    expect(cloud.count).toBe(2);
    expect(Array.from(cloud.positions.subarray(0, 6))).toEqual([1, 2, 0, 3, -1, 2]);
    expect(cloud.bounds).toMatchObject({ minX: 1, maxX: 3, minY: -1, maxY: 2, minZ: 0, maxZ: 2 });
    expect(cloud.colorRange).toEqual({ lowM: 0, highM: 2 });
    expect(Array.from(cloud.colors.subarray(0, 3))).toEqual([...HEIGHT_STOPS[0]!]);
    expect(Array.from(cloud.colors.subarray(3, 6))).toEqual([...HEIGHT_STOPS[HEIGHT_STOPS.length - 1]!]);
  });

  it('appends part of a chunk (from, count) and drops non-finite points', () => {
    const cloud = new CloudBuffer(8);
    const stored = cloud.append(xyzi([9, 9, 9], [1, 1, NaN], [2, 2, 0.5], [Infinity, 0, 0]), 3, 1);
    expect(stored).toBe(1);
    expect(Array.from(cloud.positions.subarray(0, 3))).toEqual([2, 2, 0.5]);
  });

  it('grows by doubling, keeps the points, and replaces the arrays only then', () => {
    const cloud = new CloudBuffer(1024);
    const before = cloud.positions;
    const chunk = new Float32Array(600 * 4).map((_, i) => (i % 4 === 2 ? 1 : i));
    cloud.append(chunk, 600);
    expect(cloud.positions).toBe(before); // fits: no reallocation
    expect(cloud.generation).toBe(0);
    cloud.append(chunk, 600);
    expect(cloud.capacity).toBe(2048);
    expect(cloud.generation).toBe(1);
    expect(cloud.count).toBe(1200);
    expect(cloud.positions[0]).toBe(0);
    expect(cloud.positions[3 * 600]).toBe(0); // the second chunk's first point after the copy
    expect(cloud.positions[3 * 599 + 1]).toBe(599 * 4 + 1);
    // 72 000 points (the biggest sweep) in 721-point chunks: a handful of reallocations.
    for (let i = 0; i < 100; i++) cloud.append(new Float32Array(721 * 4), 721);
    expect(cloud.generation).toBeLessThanOrEqual(7);
  });

  it('reserve() allocates up front so a whole sweep never reallocates', () => {
    const cloud = new CloudBuffer();
    cloud.reserve(sweepCapacityHint(24, 500));
    const generation = cloud.generation;
    for (let i = 0; i < 24; i++) cloud.append(new Float32Array(500 * 4), 500);
    expect(cloud.generation).toBe(generation);
    expect(cloud.count).toBe(12000);
  });

  it('recolours everything (colorVersion) only when the height scale widens', () => {
    const cloud = new CloudBuffer();
    cloud.append(xyzi([0, 0, 0], [0, 0, 1]), 2);
    const version = cloud.colorVersion;
    const topBefore = Array.from(cloud.colors.subarray(3, 6));
    cloud.append(xyzi([0, 0, 0.9]), 1); // inside the scale: only the new point is coloured
    expect(cloud.colorVersion).toBe(version);
    cloud.append(xyzi([0, 0, 2]), 1); // the scale widens to 0..2 m: z = 1 is now mid-scale
    expect(cloud.colorVersion).toBe(version + 1);
    expect(cloud.colorRange).toEqual({ lowM: 0, highM: 2 });
    expect(Array.from(cloud.colors.subarray(3, 6))).not.toEqual(topBefore);
    expect(Array.from(cloud.colors.subarray(3, 6))).toEqual(colorOf(1, 0, 2));
  });

  it('clear() empties it but keeps the arrays', () => {
    const cloud = new CloudBuffer();
    cloud.append(xyzi([1, 1, 1]), 1);
    const positions = cloud.positions;
    cloud.clear();
    expect(cloud.count).toBe(0);
    expect(cloud.clears).toBe(1);
    expect(cloud.colorRange).toBeNull();
    expect(cloud.bounds.minZ).toBe(Infinity);
    expect(cloud.positions).toBe(positions);
  });
});

describe('floor texture', () => {
  it('paints walls opaque, free floor translucent and unknown clear', () => {
    const pixels = new Uint32Array(3);
    paintFloor(Uint8Array.from([100, 0, 255]), pixels);
    expect(pixels[0]! >>> 24).toBe(255);
    expect(pixels[1]! >>> 24).toBeGreaterThan(0);
    expect(pixels[1]! >>> 24).toBeLessThan(255);
    expect(pixels[2]).toBe(0);
  });
});
