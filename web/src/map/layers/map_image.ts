// The occupancy grid (the `map` topic): free cells dark, occupied light, unknown navy. Painted once
// per map into an offscreen image of one pixel per cell, which the view transform then places.
// While a map is being built (tiles in the scene) the tiles layer draws that one instead.

import { UNKNOWN_CELL } from '../../frames';
import type { MapGrid } from '../../frames';
import type { MapFrame, MapLayer } from '../layer';
import { drawGridImage, paintedCanvas } from '../shapes';

const FREE_RGB = [46, 53, 64];
const OCCUPIED_RGB = [214, 221, 231];
const UNKNOWN_RGB = [20, 27, 45];

/** 256-entry RGBA lookup (as little-endian u32) from cell value (0..100 occupancy, else unknown) to colour. */
function buildPalette(): Uint32Array {
  const lut = new Uint32Array(256);
  const pack = (r: number, g: number, b: number, a = 255) => ((a << 24) | (b << 16) | (g << 8) | r) >>> 0;
  for (let v = 0; v < 256; v++) {
    if (v > 100) {
      lut[v] = pack(UNKNOWN_RGB[0]!, UNKNOWN_RGB[1]!, UNKNOWN_RGB[2]!);
      continue;
    }
    const k = v / 100;
    const c = FREE_RGB.map((f, i) => Math.round(f + (OCCUPIED_RGB[i]! - f) * k));
    lut[v] = pack(c[0]!, c[1]!, c[2]!);
  }
  return lut;
}

/** Cell value -> RGBA (little-endian u32, ImageData order); also paints the tiles of a map being built. */
export const OCCUPANCY_PALETTE = buildPalette();

/** Paints a grid into RGBA pixels, image row r = grid row r (flipped by the view transform). */
export function paintGrid(map: MapGrid, pixels: Uint32Array): void {
  const n = map.width * map.height;
  for (let i = 0; i < n; i++) pixels[i] = OCCUPANCY_PALETTE[map.cells[i] ?? UNKNOWN_CELL]!;
}

export class MapImageLayer implements MapLayer {
  readonly id = 'map';
  /** The map `image` was painted from; a new map object means new cells. */
  private paintedMap: MapGrid | null = null;
  private image: HTMLCanvasElement | null = null;

  draw({ ctx, view, dpr, scene }: MapFrame): void {
    const map = scene.map;
    if (!map || scene.tiles.size > 0) return;
    if (map !== this.paintedMap) this.paint(map);
    if (this.image) drawGridImage(ctx, view, dpr, this.image, map.origin, map.resolution);
  }

  private paint(map: MapGrid): void {
    this.paintedMap = map;
    const empty = map.width <= 0 || map.height <= 0;
    this.image = empty ? null : paintedCanvas(map.width, map.height, (pixels) => paintGrid(map, pixels));
  }
}
