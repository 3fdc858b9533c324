import { describe, expect, it } from 'vitest';
import { TileStore } from '../src/tile_store';
import type { TileLattice, TileUpdate } from '../src/tiles';

const LATTICE: TileLattice = { tileCells: 2, resolution: 0.5, origin: { x: -1, y: -2, theta: 0 }, mapId: 0 };

function update(tiles: [number, number, number[]][], lattice: TileLattice = LATTICE): TileUpdate {
  return { lattice, tiles: tiles.map(([x, y, cells]) => ({ x, y, cells: Uint8Array.from(cells) })) };
}

describe('tile store', () => {
  it('keys tiles by (tile_x, tile_y): a tile sent again replaces the one held', () => {
    const store = new TileStore();
    expect(store.apply(update([[0, 0, [1, 2, 3, 4]], [1, 0, [0, 0, 0, 0]]]))).toEqual({ reset: true, changed: 2, grew: true });
    expect(store.apply(update([[0, 0, [9, 9, 9, 9]]]))).toEqual({ reset: false, changed: 1, grew: false });
    expect(store.size).toBe(2);
    expect([...store.get(0, 0)!.cells]).toEqual([9, 9, 9, 9]);
    expect(store.get(0, 1)).toBeUndefined();
  });

  it('copies the cells (a frame views the socket buffer)', () => {
    const store = new TileStore();
    const u = update([[0, 0, [1, 2, 3, 4]]]);
    store.apply(u);
    u.tiles[0]!.cells[0] = 77;
    expect(store.get(0, 0)!.cells[0]).toBe(1);
  });

  it('stamps changed tiles with the version, so a painter finds what changed since it looked', () => {
    const store = new TileStore();
    store.apply(update([[0, 0, [0, 0, 0, 0]], [1, 1, [0, 0, 0, 0]]]));
    const seen = store.version;
    store.apply(update([[1, 1, [5, 5, 5, 5]]]));
    expect(store.version).toBe(seen + 1);
    const changed = [...store.values()].filter((t) => t.version > seen).map((t) => [t.x, t.y]);
    expect(changed).toEqual([[1, 1]]);
  });

  it('grows its index range and map-frame bounds with the tiles', () => {
    const store = new TileStore();
    store.apply(update([[0, 0, [0, 0, 0, 0]]]));
    // A tile is 2 cells x 0.5 m = 1 m on a side, tile (0, 0) at the origin (-1, -2).
    expect(store.bounds()).toEqual({ minX: -1, minY: -2, maxX: 0, maxY: -1 });
    expect(store.apply(update([[-2, 3, [0, 0, 0, 0]]])).grew).toBe(true);
    expect(store.indexRange()).toEqual({ minX: -2, minY: 0, maxX: 0, maxY: 3 });
    expect(store.bounds()).toEqual({ minX: -3, minY: -2, maxX: 0, maxY: 2 });
  });

  it('places tiles on a rotated lattice', () => {
    const store = new TileStore();
    const rotated = { ...LATTICE, origin: { x: 1, y: 1, theta: Math.PI / 2 } };
    store.apply(update([[1, 0, [10, 20, 30, 40]]], rotated));
    const o = store.tileOrigin(1, 0);
    expect(o.x).toBeCloseTo(1, 9);
    expect(o.y).toBeCloseTo(2, 9);
    // Lattice +x is map +y, lattice +y is map -x: columns run up the map, rows towards -x.
    expect(store.cellAt(0.9, 2.2)).toBe(10);
    expect(store.cellAt(0.9, 2.7)).toBe(20);
    expect(store.cellAt(0.2, 2.2)).toBe(30);
    expect(store.cellAt(0.2, 2.7)).toBe(40);
  });

  it('reads the cell under a map point, row 0 at the bottom; undefined outside the tiles', () => {
    const store = new TileStore();
    store.apply(update([[0, 0, [10, 20, 30, 255]]]));
    expect(store.cellAt(-0.9, -1.9)).toBe(10);
    expect(store.cellAt(-0.1, -1.9)).toBe(20);
    expect(store.cellAt(-0.9, -1.1)).toBe(30);
    expect(store.cellAt(-0.1, -1.1)).toBe(255);
    expect(store.cellAt(0.5, -1.5)).toBeUndefined();
    expect(store.knownCells()).toBe(3);
  });

  it('starts afresh on another lattice (tile size, resolution, origin or map id)', () => {
    const store = new TileStore();
    store.apply(update([[0, 0, [0, 0, 0, 0]], [1, 0, [0, 0, 0, 0]]]));
    const epoch = store.epoch;
    const moved = { ...LATTICE, origin: { x: 0, y: -2, theta: 0 } };
    expect(store.apply(update([[4, 4, [1, 1, 1, 1]]], moved)).reset).toBe(true);
    expect(store.size).toBe(1);
    expect(store.epoch).toBe(epoch + 1);
    expect(store.apply(update([[4, 4, [1, 1, 1, 1]]], { ...moved, mapId: 3 })).reset).toBe(true);
    expect(store.apply(update([[4, 4, new Array(9).fill(0)]], { ...moved, mapId: 3, tileCells: 3 })).reset).toBe(true);
    // f32 round-off of the same lattice is the same lattice.
    expect(store.apply(update([[4, 4, new Array(9).fill(0)]], { ...moved, mapId: 3, tileCells: 3, resolution: 0.5 + 1e-8 })).reset).toBe(false);
  });

  it('skips tiles of the wrong size', () => {
    const store = new TileStore();
    expect(store.apply(update([[0, 0, [1, 2, 3]], [1, 0, [1, 2, 3, 4]]])).changed).toBe(1);
    expect(store.get(0, 0)).toBeUndefined();
  });

  it('is emptied by clear (a whole map replaces the store)', () => {
    const store = new TileStore();
    store.apply(update([[0, 0, [0, 0, 0, 0]]]));
    const version = store.version;
    store.clear();
    expect(store.size).toBe(0);
    expect(store.lattice).toBeNull();
    expect(store.bounds()).toBeNull();
    expect(store.version).toBeGreaterThan(version);
    expect(store.apply(update([[0, 0, [0, 0, 0, 0]]])).reset).toBe(true);
  });
});
