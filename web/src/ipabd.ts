// The IPaBD obstacle map of a 3D sweep (docs/algorithms.md P2, GET /api/v1/sweeps/{id}/obstacle_map):
// parsing, counting the occupied cells and painting them as translucent squares for the 2D map
// overlay. Pure, so it is unit-tested.

import type { Pose2D } from './frames';

export interface JsonObstacleMap {
  sweep_id: number;
  resolution: number;
  origin: Pose2D;
  width: number;
  height: number;
  /** Row-major, row 0 at the bottom: 0 free, 100 occupied, 255 not observed. */
  data: number[];
}

export interface ObstacleGrid {
  sweepId: number;
  width: number;
  height: number;
  /** Metres per cell. */
  resolution: number;
  /** Pose of cell (0, 0)'s lower-left corner in the map frame. */
  origin: Pose2D;
  cells: Uint8Array;
}

export const NOT_OBSERVED = 255;

export function obstacleGridFromJson(json: JsonObstacleMap): ObstacleGrid {
  const { width, height } = json;
  if (!Number.isInteger(width) || !Number.isInteger(height) || width < 0 || height < 0) {
    throw new Error(`obstacle map has a bad size ${width}x${height}`);
  }
  if (!Array.isArray(json.data) || json.data.length !== width * height) {
    throw new Error(`obstacle map holds ${Array.isArray(json.data) ? json.data.length : 0} cells, ${width}x${height} expected`);
  }
  if (!(json.resolution > 0)) throw new Error(`obstacle map has a bad resolution ${json.resolution}`);
  const cells = new Uint8Array(width * height);
  for (let i = 0; i < cells.length; i++) {
    const v = json.data[i]!;
    cells[i] = v >= 0 && v <= 100 ? v : NOT_OBSERVED;
  }
  return {
    sweepId: json.sweep_id,
    width,
    height,
    resolution: json.resolution,
    origin: { x: json.origin.x, y: json.origin.y, theta: json.origin.theta ?? 0 },
    cells,
  };
}

/** Occupied: 50..100 (the server writes 100; anything nearer occupied than free counts). */
export function isObstacleCell(value: number): boolean {
  return value >= 50 && value <= 100;
}

export function countObstacleCells(grid: ObstacleGrid): number {
  let n = 0;
  for (let i = 0; i < grid.cells.length; i++) if (isObstacleCell(grid.cells[i]!)) n++;
  return n;
}

/** Image pixels per cell: enough to draw each cell as a square with an edge, the image at most ~2048 px wide. */
export function obstacleCellPixels(width: number, height: number): number {
  const longest = Math.max(width, height, 1);
  return Math.max(1, Math.min(8, Math.floor(2048 / longest)));
}

/** Overlay colours as little-endian RGBA u32 (canvas ImageData byte order r, g, b, a). */
const FILL = rgba(244, 63, 94, 110);
const EDGE = rgba(244, 63, 94, 220);

function rgba(r: number, g: number, b: number, a: number): number {
  return ((a << 24) | (b << 16) | (g << 8) | r) >>> 0;
}

/**
 * Paints the occupied cells into a (width * k) x (height * k) RGBA image, k = `cellPixels`, image
 * row r*k.. = grid row r (the view transform flips y); other pixels stay transparent. With k >= 4
 * each square gets a stronger one-pixel edge so neighbouring cells stay distinguishable.
 */
export function paintObstacleCells(grid: ObstacleGrid, pixels: Uint32Array, cellPixels: number): void {
  const k = cellPixels;
  const imageWidth = grid.width * k;
  pixels.fill(0);
  for (let row = 0; row < grid.height; row++) {
    for (let col = 0; col < grid.width; col++) {
      if (!isObstacleCell(grid.cells[row * grid.width + col]!)) continue;
      for (let dy = 0; dy < k; dy++) {
        const base = (row * k + dy) * imageWidth + col * k;
        for (let dx = 0; dx < k; dx++) {
          const edge = k >= 4 && (dx === 0 || dy === 0 || dx === k - 1 || dy === k - 1);
          pixels[base + dx] = edge ? EDGE : FILL;
        }
      }
    }
  }
}
