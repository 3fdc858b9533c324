// The map being built while mapping, as the tiles received so far, keyed by (tile_x, tile_y) on
// one lattice. A tile frame adds or replaces tiles; a frame on another lattice (other tile size,
// resolution, origin or map id) starts the store afresh, and a whole map replaces it (the view
// clears the store). Each change is stamped with a version, so a painter redraws only the tiles
// that changed since it last looked. Pure (no DOM), unit-tested.

import type { Pose2D } from './frames';
import type { TileData, TileLattice, TileUpdate } from './tiles';

const UNKNOWN = 255;

export interface StoredTile {
  x: number;
  y: number;
  cells: Uint8Array;
  /** The store's version when this tile last changed. */
  version: number;
}

/** Inclusive tile index range. */
export interface TileRange {
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

/** Axis-aligned map-frame box (the view transform's Bounds). */
export interface TileBounds {
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

export interface TileApplyResult {
  /** The lattice changed (or was first set): the tiles held before were dropped. */
  reset: boolean;
  /** Tiles added or replaced. */
  changed: number;
  /** The index range grew (a new tile outside what was known). */
  grew: boolean;
}

/** f32 lattice values compare equal within this. */
const EPS = 1e-6;

function sameLattice(a: TileLattice, b: TileLattice): boolean {
  return (
    a.tileCells === b.tileCells &&
    a.mapId === b.mapId &&
    Math.abs(a.resolution - b.resolution) <= EPS &&
    Math.abs(a.origin.x - b.origin.x) <= EPS &&
    Math.abs(a.origin.y - b.origin.y) <= EPS &&
    Math.abs(a.origin.theta - b.origin.theta) <= EPS
  );
}

const key = (x: number, y: number): string => `${x},${y}`;

export class TileStore {
  lattice: TileLattice | null = null;
  /** Bumped on every change; never goes back (a cleared store keeps counting). */
  version = 0;
  /** Bumped when the lattice changes or the store is cleared: painters start over. */
  epoch = 0;
  private readonly tiles = new Map<string, StoredTile>();
  private range: TileRange | null = null;

  get size(): number {
    return this.tiles.size;
  }

  /** Adds or replaces the update's tiles (a tile of the wrong size is skipped). */
  apply(update: TileUpdate): TileApplyResult {
    let reset = false;
    if (!this.lattice || !sameLattice(this.lattice, update.lattice)) {
      this.dropAll();
      this.lattice = { ...update.lattice, origin: { ...update.lattice.origin } };
      reset = true;
    }
    const n = this.lattice.tileCells * this.lattice.tileCells;
    let changed = 0;
    let grew = false;
    for (const tile of update.tiles) {
      if (tile.cells.length !== n || !Number.isInteger(tile.x) || !Number.isInteger(tile.y)) continue;
      if (this.put(tile)) grew = true;
      changed++;
    }
    if (changed > 0 || reset) this.version++;
    return { reset, changed, grew };
  }

  /** Drops every tile and the lattice (a whole map arrived, or mapping ended). */
  clear(): void {
    if (!this.lattice && this.tiles.size === 0) return;
    this.dropAll();
    this.lattice = null;
    this.version++;
  }

  get(x: number, y: number): StoredTile | undefined {
    return this.tiles.get(key(x, y));
  }

  values(): IterableIterator<StoredTile> {
    return this.tiles.values();
  }

  /** Tile indices held, or null when empty. */
  indexRange(): TileRange | null {
    return this.range ? { ...this.range } : null;
  }

  /** Map-frame pose of tile (x, y)'s lower-left corner. */
  tileOrigin(x: number, y: number): Pose2D {
    const l = this.lattice;
    if (!l) return { x: 0, y: 0, theta: 0 };
    const side = l.tileCells * l.resolution;
    const c = Math.cos(l.origin.theta);
    const s = Math.sin(l.origin.theta);
    const lx = x * side;
    const ly = y * side;
    return { x: l.origin.x + c * lx - s * ly, y: l.origin.y + s * lx + c * ly, theta: l.origin.theta };
  }

  /** The map-frame box around the tiles held (corners of the rotated range), or null. */
  bounds(): TileBounds | null {
    const r = this.range;
    if (!r || !this.lattice) return null;
    const corners = [
      this.tileOrigin(r.minX, r.minY),
      this.tileOrigin(r.maxX + 1, r.minY),
      this.tileOrigin(r.maxX + 1, r.maxY + 1),
      this.tileOrigin(r.minX, r.maxY + 1),
    ];
    return {
      minX: Math.min(...corners.map((p) => p.x)),
      minY: Math.min(...corners.map((p) => p.y)),
      maxX: Math.max(...corners.map((p) => p.x)),
      maxY: Math.max(...corners.map((p) => p.y)),
    };
  }

  /** The cell at map point (x, y): 0..100, 255 unknown, undefined where no tile was received. */
  cellAt(x: number, y: number): number | undefined {
    const l = this.lattice;
    if (!l) return undefined;
    const dx = x - l.origin.x;
    const dy = y - l.origin.y;
    const c = Math.cos(l.origin.theta);
    const s = Math.sin(l.origin.theta);
    // Into the lattice frame, then cells.
    const col = Math.floor((c * dx + s * dy) / l.resolution);
    const row = Math.floor((-s * dx + c * dy) / l.resolution);
    const tx = Math.floor(col / l.tileCells);
    const ty = Math.floor(row / l.tileCells);
    const tile = this.get(tx, ty);
    if (!tile) return undefined;
    return tile.cells[(row - ty * l.tileCells) * l.tileCells + (col - tx * l.tileCells)];
  }

  /** Cells that are not unknown, over every tile. */
  knownCells(): number {
    let n = 0;
    for (const tile of this.tiles.values()) for (const v of tile.cells) if (v !== UNKNOWN) n++;
    return n;
  }

  /** Stores one tile (its cells copied: a frame's bytes are a view into the socket's buffer); true when the range grew. */
  private put(tile: TileData): boolean {
    this.tiles.set(key(tile.x, tile.y), { x: tile.x, y: tile.y, cells: tile.cells.slice(), version: this.version + 1 });
    const r = this.range;
    if (!r) {
      this.range = { minX: tile.x, minY: tile.y, maxX: tile.x, maxY: tile.y };
      return true;
    }
    if (tile.x >= r.minX && tile.x <= r.maxX && tile.y >= r.minY && tile.y <= r.maxY) return false;
    r.minX = Math.min(r.minX, tile.x);
    r.minY = Math.min(r.minY, tile.y);
    r.maxX = Math.max(r.maxX, tile.x);
    r.maxY = Math.max(r.maxY, tile.y);
    return true;
  }

  private dropAll(): void {
    this.tiles.clear();
    this.range = null;
    this.epoch++;
  }
}
