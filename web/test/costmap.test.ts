import { describe, expect, it } from 'vitest';
import {
  COST_PALETTE,
  costClass,
  costColor,
  costmapFromJson,
  countCosts,
  decodeCostmapBody,
  INFLATED_HIGH_RGBA,
  INFLATED_LOW_RGBA,
  LETHAL_RGBA,
  paintCosts,
} from '../src/costmap';
import { decodeBinaryFrame, FrameError } from '../src/frames';
import { costmapBody, frame } from './frame_bytes';

describe('costmap frames (topic 4)', () => {
  it('decode size, resolution, origin, which and the costs of the global costmap', () => {
    const costs = [0, 1, 128, 252, 253, 254, 255, 0];
    const f = decodeBinaryFrame(frame(4, costmapBody(4, 2, costs, { which: 0, resolution: 0.1, origin: [1.5, -2, 0.25] }), { seq: 4 }));
    expect(f.kind).toBe('costmap');
    if (f.kind !== 'costmap') return;
    expect(f.header.topic).toBe('costmap');
    const c = f.costmap;
    expect([c.which, c.width, c.height]).toEqual(['global', 4, 2]);
    expect(c.resolution).toBeCloseTo(0.1, 6);
    expect([c.origin.x, c.origin.y]).toEqual([1.5, -2]);
    expect(c.origin.theta).toBeCloseTo(0.25, 6);
    expect([...c.costs]).toEqual(costs);
  });

  it('tell the local costmap (which 1) from the global one', () => {
    const c = decodeCostmapBody(costmapBody(1, 1, [254], { which: 1 }), 0);
    expect(c.which).toBe('local');
  });

  it('honour a longer header', () => {
    const f = decodeBinaryFrame(frame(4, costmapBody(2, 1, [7, 8]), { headerBytes: 40 }));
    expect(f.kind === 'costmap' && [...f.costmap.costs]).toEqual([7, 8]);
  });

  it('refuse truncated or oversized bodies and an unknown which', () => {
    const good = costmapBody(3, 3, new Array(9).fill(0));
    expect(() => decodeCostmapBody(good.slice(0, good.byteLength - 1), 0)).toThrow(FrameError);
    const long = new Uint8Array(good.byteLength + 1);
    long.set(new Uint8Array(good));
    expect(() => decodeCostmapBody(long.buffer, 0)).toThrow(FrameError);
    expect(() => decodeCostmapBody(costmapBody(1, 1, [0], { which: 2 }), 0)).toThrow(/which/);
    expect(() => decodeCostmapBody(new ArrayBuffer(16), 0)).toThrow(/too short/);
  });

  it('have a JSON twin', () => {
    const c = costmapFromJson({ which: 'local', width: 2, height: 2, resolution: 0.05, origin: { x: 0, y: 1, theta: 0 }, data: [0, 253, 254, -1] });
    expect(c.which).toBe('local');
    expect([...c.costs]).toEqual([0, 253, 254, 255]);
    expect(() => costmapFromJson({ which: 'global', width: 2, height: 2, resolution: 0.05, origin: { x: 0, y: 0, theta: 0 }, data: [0] })).toThrow(FrameError);
    expect(() => costmapFromJson({ which: 'both', width: 0, height: 0, resolution: 0.05, origin: { x: 0, y: 0, theta: 0 }, data: [] })).toThrow(/which/);
  });
});

describe('cost classes and colours', () => {
  it('follow ROS costmap_2d: 0 free, 1..252 inflated, 253 inscribed, 254 lethal, 255 unknown', () => {
    expect([0, 1, 100, 252, 253, 254, 255].map(costClass)).toEqual(['free', 'inflated', 'inflated', 'inflated', 'inscribed', 'lethal', 'unknown']);
    expect(countCosts({ costs: Uint8Array.of(0, 0, 5, 253, 254, 254, 255) })).toEqual({ free: 2, inflated: 1, inscribed: 1, lethal: 2, unknown: 1 });
  });

  it('run the inflated gradient from its low to its high colour', () => {
    expect(costColor(1)).toEqual(INFLATED_LOW_RGBA);
    expect(costColor(252)).toEqual([...INFLATED_HIGH_RGBA.slice(0, 3), INFLATED_HIGH_RGBA[3]]);
    const mid = costColor(126);
    expect(mid[3]).toBeGreaterThan(INFLATED_LOW_RGBA[3]);
    expect(mid[3]).toBeLessThan(INFLATED_HIGH_RGBA[3]);
    expect(costColor(254)).toEqual(LETHAL_RGBA);
  });

  it('paint pixels from the palette (RGBA bytes in ImageData order)', () => {
    const pixels = new Uint32Array(2);
    paintCosts({ costs: Uint8Array.of(254, 0) }, pixels);
    expect(pixels[0]).toBe(COST_PALETTE[254]);
    const bytes = new Uint8Array(pixels.buffer);
    expect([...bytes.slice(0, 4)]).toEqual([LETHAL_RGBA[0], LETHAL_RGBA[1], LETHAL_RGBA[2], Math.round(LETHAL_RGBA[3] * 255)]);
  });
});
