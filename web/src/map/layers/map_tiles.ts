// The map being built while mapping (the `map` topic's tile frames, held in the scene's tile
// store): the tiles as one mosaic image on the tile lattice, painted with the occupancy colours of
// the whole map. Only the tiles that changed since the last frame are repainted; the mosaic is
// reallocated (with room to grow) when a tile falls outside it. Tiles not received are clear, so
// the grid shows through. The number of tiles drawn is published as the canvas's data-tiles.

import type { TileRange, TileStore } from '../../tile_store';
import type { MapFrame, MapLayer } from '../layer';
import { drawGridImage } from '../shapes';
import { OCCUPANCY_PALETTE } from './map_image';

/** Tiles of room left around the received ones when the mosaic is (re)allocated. */
const GROW_TILES = 2;
/** A mosaic side beyond this many pixels gets no room to grow. */
const MAX_MOSAIC_PX = 8192;

interface Mosaic {
  canvas: HTMLCanvasElement;
  ctx: CanvasRenderingContext2D;
  image: ImageData;
  pixels: Uint32Array;
  range: TileRange;
  epoch: number;
  /** The store's version last painted. */
  version: number;
}

/** Writes a tile's cells into mosaic pixels (row 0 at the bottom = image row 0, flipped by the view). */
export function paintTileInto(pixels: Uint32Array, mosaicWidth: number, cells: Uint8Array, tileCells: number, offsetX: number, offsetY: number): void {
  for (let r = 0; r < tileCells; r++) {
    const row = (offsetY + r) * mosaicWidth + offsetX;
    const src = r * tileCells;
    for (let c = 0; c < tileCells; c++) pixels[row + c] = OCCUPANCY_PALETTE[cells[src + c]!]!;
  }
}

/** Whether `inner` lies within `outer`. */
function inside(inner: TileRange, outer: TileRange): boolean {
  return inner.minX >= outer.minX && inner.minY >= outer.minY && inner.maxX <= outer.maxX && inner.maxY <= outer.maxY;
}

export class MapTilesLayer implements MapLayer {
  readonly id = 'mapTiles';
  /** Tiles in the last frame drawn. */
  tilesDrawn = 0;
  private mosaic: Mosaic | null = null;

  draw({ ctx, view, dpr, scene, canvas }: MapFrame): void {
    const store = scene.tiles;
    const range = store.indexRange();
    const lattice = store.lattice;
    if (!range || !lattice) {
      this.mosaic = null;
      this.publish(canvas, 0);
      return;
    }
    const mosaic = this.update(store, range, lattice.tileCells);
    this.publish(canvas, mosaic ? store.size : 0);
    if (!mosaic) return;
    drawGridImage(ctx, view, dpr, mosaic.canvas, store.tileOrigin(mosaic.range.minX, mosaic.range.minY), lattice.resolution);
  }

  private publish(canvas: HTMLCanvasElement, drawn: number): void {
    this.tilesDrawn = drawn;
    const text = String(drawn);
    if (canvas.dataset.tiles !== text) canvas.dataset.tiles = text;
  }

  /** Brings the mosaic up to the store's version; null without 2D. */
  private update(store: TileStore, range: TileRange, tileCells: number): Mosaic | null {
    let mosaic = this.mosaic;
    if (!mosaic || mosaic.epoch !== store.epoch || !inside(range, mosaic.range)) {
      mosaic = this.allocate(range, tileCells, store.epoch);
      this.mosaic = mosaic;
      if (!mosaic) return null;
      mosaic.version = -1; // everything is new to this mosaic
    }
    if (mosaic.version === store.version) return mosaic;
    const width = mosaic.canvas.width;
    let dirty: { x0: number; y0: number; x1: number; y1: number } | null = null;
    for (const tile of store.values()) {
      if (tile.version <= mosaic.version) continue;
      const ox = (tile.x - mosaic.range.minX) * tileCells;
      const oy = (tile.y - mosaic.range.minY) * tileCells;
      paintTileInto(mosaic.pixels, width, tile.cells, tileCells, ox, oy);
      dirty = dirty
        ? { x0: Math.min(dirty.x0, ox), y0: Math.min(dirty.y0, oy), x1: Math.max(dirty.x1, ox + tileCells), y1: Math.max(dirty.y1, oy + tileCells) }
        : { x0: ox, y0: oy, x1: ox + tileCells, y1: oy + tileCells };
    }
    if (dirty) mosaic.ctx.putImageData(mosaic.image, 0, 0, dirty.x0, dirty.y0, dirty.x1 - dirty.x0, dirty.y1 - dirty.y0);
    mosaic.version = store.version;
    return mosaic;
  }

  private allocate(range: TileRange, tileCells: number, epoch: number): Mosaic | null {
    const spanX = range.maxX - range.minX + 1;
    const spanY = range.maxY - range.minY + 1;
    const room = (spanX + 2 * GROW_TILES) * tileCells <= MAX_MOSAIC_PX && (spanY + 2 * GROW_TILES) * tileCells <= MAX_MOSAIC_PX ? GROW_TILES : 0;
    const grown: TileRange = { minX: range.minX - room, minY: range.minY - room, maxX: range.maxX + room, maxY: range.maxY + room };
    const width = (grown.maxX - grown.minX + 1) * tileCells;
    const height = (grown.maxY - grown.minY + 1) * tileCells;
    const canvas = document.createElement('canvas');
    canvas.width = width;
    canvas.height = height;
    const ctx = canvas.getContext('2d');
    if (!ctx) return null;
    const image = ctx.createImageData(width, height);
    return { canvas, ctx, image, pixels: new Uint32Array(image.data.buffer), range: grown, epoch, version: -1 };
  }
}
