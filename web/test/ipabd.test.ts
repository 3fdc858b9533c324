import { describe, expect, it } from 'vitest';
import { countObstacleCells, NOT_OBSERVED, obstacleCellPixels, obstacleGridFromJson, paintObstacleCells } from '../src/ipabd';

const json = {
  sweep_id: 3,
  resolution: 0.2,
  origin: { x: -4, y: -4, theta: 0 },
  width: 3,
  height: 2,
  // row 0 (bottom): occupied, free, not observed; row 1: free, occupied, occupied
  data: [100, 0, 255, 0, 100, 100],
};

describe('IPaBD obstacle map', () => {
  it('parses the JSON and counts the occupied cells', () => {
    const grid = obstacleGridFromJson(json);
    expect(grid).toMatchObject({ sweepId: 3, width: 3, height: 2, resolution: 0.2, origin: { x: -4, y: -4, theta: 0 } });
    expect(Array.from(grid.cells)).toEqual([100, 0, NOT_OBSERVED, 0, 100, 100]);
    expect(countObstacleCells(grid)).toBe(3);
  });

  it('maps out-of-range values to not observed and rejects a size mismatch', () => {
    expect(Array.from(obstacleGridFromJson({ ...json, data: [-1, 0, 101, 0, 0, 0] }).cells.subarray(0, 3))).toEqual([NOT_OBSERVED, 0, NOT_OBSERVED]);
    expect(() => obstacleGridFromJson({ ...json, data: [0, 0] })).toThrow(/2 cells, 3x2 expected/);
    expect(() => obstacleGridFromJson({ ...json, resolution: 0 })).toThrow(/resolution/);
  });

  it('picks up to 8 pixels per cell, keeping the image near 2048 px', () => {
    expect(obstacleCellPixels(40, 40)).toBe(8);
    expect(obstacleCellPixels(400, 300)).toBe(5);
    expect(obstacleCellPixels(5000, 10)).toBe(1);
  });

  it('paints occupied cells as squares with an edge, the rest transparent', () => {
    const grid = obstacleGridFromJson(json);
    const k = 4;
    const pixels = new Uint32Array(grid.width * k * grid.height * k).fill(0xdeadbeef);
    paintObstacleCells(grid, pixels, k);
    const at = (x: number, y: number) => pixels[y * grid.width * k + x]!;
    const alpha = (p: number) => p >>> 24;
    // Cell (0, 0): edge pixel stronger than the inside.
    expect(alpha(at(0, 0))).toBeGreaterThan(alpha(at(1, 1)));
    expect(alpha(at(1, 1))).toBeGreaterThan(0);
    expect(alpha(at(1, 1))).toBeLessThan(255); // translucent
    // Cell (1, 0) free and (2, 0) not observed: clear.
    expect(at(k + 1, 1)).toBe(0);
    expect(at(2 * k + 1, 1)).toBe(0);
    // Row 1 = image rows k..2k-1: cells (1, 1) and (2, 1) occupied, (0, 1) not.
    expect(alpha(at(k + 1, k + 1))).toBeGreaterThan(0);
    expect(at(1, k + 1)).toBe(0);
    let painted = 0;
    for (const p of pixels) if (p !== 0) painted++;
    expect(painted).toBe(3 * k * k);
  });
});
