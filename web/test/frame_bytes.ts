// Builders of binary frames for the decoder tests, byte by byte as README "Binary frames" and the
// layouts of tile, costmap and particles bodies say (little-endian, 32-byte header).

export function frame(topicId: number, body: ArrayBuffer, opts: { seq?: number; t?: number; wallUs?: number; headerBytes?: number } = {}): ArrayBuffer {
  const headerBytes = opts.headerBytes ?? 32;
  const buffer = new ArrayBuffer(headerBytes + body.byteLength);
  const view = new DataView(buffer);
  'MBT1'.split('').forEach((c, i) => view.setUint8(i, c.charCodeAt(0)));
  view.setUint16(4, topicId, true);
  view.setUint16(6, headerBytes, true);
  view.setBigUint64(8, BigInt(opts.seq ?? 1), true);
  view.setFloat64(16, opts.t ?? 0, true);
  view.setBigInt64(24, BigInt(opts.wallUs ?? 0), true);
  new Uint8Array(buffer, headerBytes).set(new Uint8Array(body));
  return buffer;
}

export interface TileSpec {
  x: number;
  y: number;
  /** tileCells^2 cells, or one value for every cell. */
  cells: number[] | number;
}

/** A map body with flags bit 0: tile_cells, count, resolution, origin, map id, flags, then per tile i32 x, i32 y, cells. */
export function tileBody(tileCells: number, tiles: TileSpec[], opts: { resolution?: number; origin?: [number, number, number]; mapId?: number; flags?: number; count?: number } = {}): ArrayBuffer {
  const n = tileCells * tileCells;
  const body = new ArrayBuffer(32 + tiles.length * (8 + n));
  const view = new DataView(body);
  const [ox, oy, ot] = opts.origin ?? [-3.2, -1.6, 0];
  view.setUint32(0, tileCells, true);
  view.setUint32(4, opts.count ?? tiles.length, true);
  view.setFloat32(8, opts.resolution ?? 0.05, true);
  view.setFloat32(12, ox, true);
  view.setFloat32(16, oy, true);
  view.setFloat32(20, ot, true);
  view.setUint32(24, opts.mapId ?? 0, true);
  view.setUint32(28, opts.flags ?? 1, true);
  tiles.forEach((t, i) => {
    const at = 32 + i * (8 + n);
    view.setInt32(at, t.x, true);
    view.setInt32(at + 4, t.y, true);
    const cells = typeof t.cells === 'number' ? new Array<number>(n).fill(t.cells) : t.cells;
    new Uint8Array(body, at + 8, n).set(cells);
  });
  return body;
}

/** A costmap body: width, height, resolution, origin, which (0 global, 1 local), reserved, costs. */
export function costmapBody(width: number, height: number, costs: number[], opts: { which?: number; resolution?: number; origin?: [number, number, number] } = {}): ArrayBuffer {
  const body = new ArrayBuffer(32 + costs.length);
  const view = new DataView(body);
  const [ox, oy, ot] = opts.origin ?? [1.5, -2, 0];
  view.setUint32(0, width, true);
  view.setUint32(4, height, true);
  view.setFloat32(8, opts.resolution ?? 0.1, true);
  view.setFloat32(12, ox, true);
  view.setFloat32(16, oy, true);
  view.setFloat32(20, ot, true);
  view.setUint32(24, opts.which ?? 0, true);
  view.setUint32(28, 0, true);
  new Uint8Array(body, 32).set(costs);
  return body;
}

/** A particles body: count, total, six reserved u32, then x, y, theta, weight (f32) per particle. */
export function particlesBody(particles: number[][], opts: { count?: number; total?: number } = {}): ArrayBuffer {
  const body = new ArrayBuffer(32 + particles.length * 16);
  const view = new DataView(body);
  view.setUint32(0, opts.count ?? particles.length, true);
  view.setUint32(4, opts.total ?? particles.length, true);
  particles.forEach((p, i) => p.forEach((v, k) => view.setFloat32(32 + 16 * i + 4 * k, v, true)));
  return body;
}
