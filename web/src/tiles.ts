// Tile frames of the `map` topic while mapping: the changed tile_cells x tile_cells tiles of the
// map being built, on a fixed lattice of the map frame, so the map grows without resending what is
// known. Binary: a map body with flags bit 0 set (README "Binary frames"); JSON: the `map` data with
// `tile_cells` and a `tiles` list. Pure (no DOM), unit-tested.

import { FrameError } from './frame_error';
import type { JsonPose, Pose2D } from './frames';

/** Bit 0 of a map body's flags (offset 28): the frame carries tiles, not a whole map. */
export const MAP_FLAG_TILES = 1;
/** Body header before the first tile. */
export const TILE_BODY_HEADER_BYTES = 32;
/** tile_x and tile_y (i32 each) before a tile's cells. */
const TILE_HEAD_BYTES = 8;
/** Cell value of an unknown cell (the whole map's UNKNOWN_CELL; not imported, frames.ts imports this module). */
const UNKNOWN = 255;
/** A tile side beyond this is not a tile but a corrupt frame. */
const MAX_TILE_CELLS = 4096;

/** Where the tiles sit: tile (i, j)'s lower-left corner is at origin + R(theta) (i, j) * tileCells * resolution. */
export interface TileLattice {
  tileCells: number;
  /** m per cell. */
  resolution: number;
  /** Tile (0, 0)'s lower-left corner, map frame. */
  origin: Pose2D;
  /** 0: the map being built. */
  mapId: number;
}

/** One tile: tileCells^2 cells, row-major, row 0 at the bottom, 0..100 occupancy %, 255 unknown. */
export interface TileData {
  x: number;
  y: number;
  cells: Uint8Array;
}

export interface TileUpdate {
  lattice: TileLattice;
  tiles: TileData[];
}

/** A tile frame's body at `bodyOffset`; it must hold exactly `count` tiles. */
export function decodeTileBody(buffer: ArrayBuffer, bodyOffset: number): TileUpdate {
  if (buffer.byteLength < bodyOffset + TILE_BODY_HEADER_BYTES) throw new FrameError('tile body too short');
  const view = new DataView(buffer, bodyOffset);
  const tileCells = view.getUint32(0, true);
  const count = view.getUint32(4, true);
  if (tileCells < 1 || tileCells > MAX_TILE_CELLS) throw new FrameError(`bad tile_cells ${tileCells}`);
  if ((view.getUint32(28, true) & MAP_FLAG_TILES) === 0) throw new FrameError('not a tile frame (flags bit 0 clear)');
  const cellsPerTile = tileCells * tileCells;
  const tileBytes = TILE_HEAD_BYTES + cellsPerTile;
  const bodyBytes = buffer.byteLength - bodyOffset - TILE_BODY_HEADER_BYTES;
  if (bodyBytes !== count * tileBytes) {
    throw new FrameError(`tile body holds ${bodyBytes} bytes, ${count} tiles of ${tileCells}x${tileCells} need ${count * tileBytes}`);
  }
  const tiles: TileData[] = [];
  for (let i = 0; i < count; i++) {
    const at = bodyOffset + TILE_BODY_HEADER_BYTES + i * tileBytes;
    const head = new DataView(buffer, at, TILE_HEAD_BYTES);
    tiles.push({
      x: head.getInt32(0, true),
      y: head.getInt32(4, true),
      cells: new Uint8Array(buffer, at + TILE_HEAD_BYTES, cellsPerTile),
    });
  }
  return {
    lattice: {
      tileCells,
      resolution: view.getFloat32(8, true),
      origin: { x: view.getFloat32(12, true), y: view.getFloat32(16, true), theta: view.getFloat32(20, true) },
      mapId: view.getUint32(24, true),
    },
    tiles,
  };
}

/** The JSON tile update: `{"tiles":[{"x","y","data"}],"id","tile_cells","resolution","origin"}`. */
export interface JsonTiles {
  id?: number;
  tile_cells: number;
  resolution: number;
  origin: JsonPose;
  tiles?: unknown;
}

/** Whether `map` topic data is a tile update (it has `tile_cells`) rather than a whole map. */
export function isTileJson(data: unknown): data is JsonTiles {
  return !!data && typeof data === 'object' && typeof (data as { tile_cells?: unknown }).tile_cells === 'number';
}

/** Cells -1 and anything outside 0..100 become unknown (255). */
export function tilesFromJson(data: JsonTiles): TileUpdate {
  const tileCells = data.tile_cells;
  if (!(tileCells >= 1 && tileCells <= MAX_TILE_CELLS) || !Number.isInteger(tileCells)) throw new FrameError(`bad tile_cells ${tileCells}`);
  const n = tileCells * tileCells;
  // The layout's example writes `"tiles":true` before the list: a duplicate key whose last value
  // (the list) is what JSON.parse keeps; `true` alone means an update without tiles.
  const rows = Array.isArray(data.tiles) ? (data.tiles as unknown[]) : [];
  const tiles: TileData[] = [];
  for (const row of rows) {
    const t = row as { x?: unknown; y?: unknown; data?: unknown };
    if (typeof t?.x !== 'number' || typeof t.y !== 'number' || !Array.isArray(t.data)) throw new FrameError('bad tile in JSON');
    if (t.data.length !== n) throw new FrameError(`tile (${t.x}, ${t.y}) holds ${t.data.length} cells, not ${n}`);
    const cells = new Uint8Array(n);
    for (let i = 0; i < n; i++) {
      const v = t.data[i];
      cells[i] = typeof v === 'number' && v >= 0 && v <= 100 ? Math.round(v) : UNKNOWN;
    }
    tiles.push({ x: t.x, y: t.y, cells });
  }
  return {
    lattice: {
      tileCells,
      resolution: data.resolution,
      origin: { x: data.origin.x, y: data.origin.y, theta: data.origin.theta ?? 0 },
      mapId: data.id ?? 0,
    },
    tiles,
  };
}
