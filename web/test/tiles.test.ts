import { describe, expect, it } from 'vitest';
import { decodeBinaryFrame, FrameError } from '../src/frames';
import { decodeTileBody, isTileJson, tilesFromJson } from '../src/tiles';
import { frame, tileBody } from './frame_bytes';

describe('tile frames (map topic, flags bit 0)', () => {
  it('decode tile_cells, lattice, map id and each tile with its cells', () => {
    const a = Array.from({ length: 16 }, (_, i) => (i === 15 ? 255 : i));
    const body = tileBody(4, [{ x: -1, y: 2, cells: a }, { x: 3, y: -4, cells: 100 }], { resolution: 0.05, origin: [-3.2, -1.6, 0.5], mapId: 0 });
    const f = decodeBinaryFrame(frame(2, body, { seq: 9, t: 3.5 }));
    expect(f.kind).toBe('tiles');
    if (f.kind !== 'tiles') return;
    expect(f.header).toMatchObject({ topic: 'map', seq: 9, t: 3.5 });
    const { lattice, tiles } = f.tiles;
    expect(lattice.tileCells).toBe(4);
    expect(lattice.resolution).toBeCloseTo(0.05, 6);
    expect(lattice.origin.x).toBeCloseTo(-3.2, 5);
    expect(lattice.origin.y).toBeCloseTo(-1.6, 5);
    expect(lattice.origin.theta).toBeCloseTo(0.5, 6);
    expect(lattice.mapId).toBe(0);
    expect(tiles.map((t) => [t.x, t.y])).toEqual([[-1, 2], [3, -4]]);
    expect([...tiles[0]!.cells]).toEqual(a);
    expect([...tiles[1]!.cells]).toEqual(new Array(16).fill(100));
  });

  it('leave whole maps (flags 0) to the map decoder', () => {
    const body = tileBody(2, [], { flags: 0 });
    // A whole map of 2 x 0 cells: the first u32 is the width.
    const f = decodeBinaryFrame(frame(2, body));
    expect(f.kind).toBe('map');
  });

  it('honour a header longer than 32 bytes', () => {
    const f = decodeBinaryFrame(frame(2, tileBody(2, [{ x: 0, y: 0, cells: [1, 2, 3, 4] }]), { headerBytes: 48 }));
    expect(f.kind === 'tiles' && [...f.tiles.tiles[0]!.cells]).toEqual([1, 2, 3, 4]);
  });

  it('refuse a body whose tiles disagree with the count or the tile size', () => {
    expect(() => decodeTileBody(tileBody(2, [{ x: 0, y: 0, cells: 0 }], { count: 2 }), 0)).toThrow(FrameError);
    expect(() => decodeTileBody(tileBody(2, [{ x: 0, y: 0, cells: 0 }], { count: 0 }), 0)).toThrow(FrameError);
    expect(() => decodeTileBody(tileBody(0, []), 0)).toThrow(/tile_cells/);
    expect(() => decodeTileBody(new ArrayBuffer(20), 0)).toThrow(/too short/);
    expect(() => decodeTileBody(tileBody(2, [], { flags: 0 }), 0)).toThrow(/flags/);
  });

  it('have a JSON twin: -1 and out-of-range cells are unknown', () => {
    const json = JSON.parse(
      '{"tiles":true,"id":0,"tile_cells":2,"resolution":0.05,"origin":{"x":1,"y":2,"theta":0},"tiles":[{"x":5,"y":-1,"data":[0,100,-1,50]}]}',
    );
    expect(isTileJson(json)).toBe(true);
    expect(isTileJson({ id: 3, width: 2, height: 2, data: [] })).toBe(false);
    const update = tilesFromJson(json);
    expect(update.lattice).toEqual({ tileCells: 2, resolution: 0.05, origin: { x: 1, y: 2, theta: 0 }, mapId: 0 });
    expect(update.tiles.map((t) => [t.x, t.y, [...t.cells]])).toEqual([[5, -1, [0, 100, 255, 50]]]);
    expect(() => tilesFromJson({ ...json, tiles: [{ x: 0, y: 0, data: [1] }] })).toThrow(FrameError);
    expect(tilesFromJson({ ...json, tiles: true }).tiles).toEqual([]);
  });
});
