// Point storage of the 3D view: a growing buffer of map-frame points with a colour per point by
// height. No three.js here: chunks are collected before the (lazily loaded) 3D view exists, the
// view wraps these arrays as GPU buffers without copying, and the logic is unit-tested in Node.

import { CLOUD_FLOATS_PER_POINT } from './frames';

/** The tilting laser's most points per scan (180 deg at 0.25 deg): caps the capacity hint. */
export const MAX_POINTS_PER_SCAN = 721;
/** The colour scale's ends snap outward to this step, so a full recolour happens a few times per sweep, not per chunk. */
export const HEIGHT_STEP_M = 0.25;
const MIN_CAPACITY = 1024;

export interface HeightRange {
  lowM: number;
  highM: number;
}

/** Colour stops of the height scale, low (floor) to high: blue, cyan, green, yellow, orange, red. */
export const HEIGHT_STOPS: readonly (readonly [number, number, number])[] = [
  [44, 62, 153],
  [31, 155, 209],
  [47, 201, 138],
  [214, 224, 64],
  [245, 155, 50],
  [232, 69, 60],
];

const LUT_SIZE = 256;
/** HEIGHT_STOPS interpolated into LUT_SIZE rgb triples: colouring 72 000 points is a table look-up each. */
const HEIGHT_LUT: Uint8Array = (() => {
  const lut = new Uint8Array(LUT_SIZE * 3);
  const segments = HEIGHT_STOPS.length - 1;
  for (let i = 0; i < LUT_SIZE; i++) {
    const t = (i / (LUT_SIZE - 1)) * segments;
    const k = Math.min(Math.floor(t), segments - 1);
    const f = t - k;
    const a = HEIGHT_STOPS[k]!;
    const b = HEIGHT_STOPS[k + 1]!;
    for (let c = 0; c < 3; c++) lut[3 * i + c] = Math.round(a[c]! + (b[c]! - a[c]!) * f);
  }
  return lut;
})();

/** Writes the rgb (0..255) of height `zM` on the scale `range` to out[offset..offset+2]; outside the range it clamps. */
export function heightColor(zM: number, range: HeightRange, out: Uint8Array, offset: number): void {
  const span = range.highM - range.lowM;
  let t = span > 0 ? (zM - range.lowM) / span : 0;
  if (!(t > 0)) t = 0; // also NaN
  if (t > 1) t = 1;
  const i = 3 * Math.round(t * (LUT_SIZE - 1));
  out[offset] = HEIGHT_LUT[i]!;
  out[offset + 1] = HEIGHT_LUT[i + 1]!;
  out[offset + 2] = HEIGHT_LUT[i + 2]!;
}

/** CSS gradient of the height scale, bottom (low) to top (high), for the legend. */
export function heightLegendGradient(): string {
  const last = HEIGHT_STOPS.length - 1;
  const stops = HEIGHT_STOPS.map(([r, g, b], i) => `rgb(${r}, ${g}, ${b}) ${Math.round((i / last) * 100)}%`);
  return `linear-gradient(to top, ${stops.join(', ')})`;
}

/** The colour scale for points spanning [zMinM, zMaxM]: the ends snapped outward to HEIGHT_STEP_M, at least one step wide. */
export function snappedHeightRange(zMinM: number, zMaxM: number): HeightRange {
  const lowM = Math.floor(zMinM / HEIGHT_STEP_M) * HEIGHT_STEP_M;
  let highM = Math.ceil(zMaxM / HEIGHT_STEP_M) * HEIGHT_STEP_M;
  if (highM - lowM < HEIGHT_STEP_M) highM = lowM + HEIGHT_STEP_M;
  return { lowM, highM };
}

/** The capacity (points) to hold `needed` points: unchanged when it fits, otherwise doubled (or `needed` when more). */
export function grownCapacity(current: number, needed: number): number {
  if (needed <= current) return current;
  return Math.max(needed, current * 2, MIN_CAPACITY);
}

/** A capacity hint for a sweep from its first chunk: one chunk per scan, each about as large as the first. */
export function sweepCapacityHint(scansTotal: number, firstChunkPoints: number): number {
  const perScan = Math.min(Math.max(firstChunkPoints, 1), MAX_POINTS_PER_SCAN);
  return Math.max(scansTotal, 1) * perScan;
}

/**
 * The points of one sweep. `positions` (x, y, z per point) and `colors` (rgb bytes per point) are
 * allocated for `capacity` points and only replaced when they must grow (doubling). Points past
 * `count` are unused. A view uploads [its uploaded count, count) after each change, all of it
 * after a change of `generation`, `colorVersion` (colours only) or `clears`.
 */
export class CloudBuffer {
  positions: Float32Array;
  colors: Uint8Array;
  count = 0;
  /** Bumped when the arrays are replaced (grown): GPU buffers must be made anew. */
  generation = 0;
  /** Bumped when every stored colour changed. */
  colorVersion = 0;
  /** Bumped by clear(): everything uploaded before is stale. */
  clears = 0;
  /** Extent of the stored points (m, map frame); +-Infinity while empty. */
  readonly bounds = { minX: Infinity, minY: Infinity, minZ: Infinity, maxX: -Infinity, maxY: -Infinity, maxZ: -Infinity };
  /** The current colour scale, or null while empty. */
  colorRange: HeightRange | null = null;

  constructor(capacity = MIN_CAPACITY) {
    this.positions = new Float32Array(capacity * 3);
    this.colors = new Uint8Array(capacity * 3);
  }

  get capacity(): number {
    return this.positions.length / 3;
  }

  /** Empties the buffer, keeping its arrays for the next sweep. */
  clear(): void {
    this.count = 0;
    this.colorRange = null;
    const b = this.bounds;
    b.minX = b.minY = b.minZ = Infinity;
    b.maxX = b.maxY = b.maxZ = -Infinity;
    this.clears++;
  }

  /** Makes room for `points` points in total, growing (copying the stored points) only when needed. */
  reserve(points: number): void {
    const capacity = grownCapacity(this.capacity, points);
    if (capacity === this.capacity) return;
    const positions = new Float32Array(capacity * 3);
    positions.set(this.positions.subarray(0, this.count * 3));
    const colors = new Uint8Array(capacity * 3);
    colors.set(this.colors.subarray(0, this.count * 3));
    this.positions = positions;
    this.colors = colors;
    this.generation++;
  }

  /**
   * Appends `count` points given as x, y, z, intensity floats (the cloud frame's layout) starting
   * at point `from` of `points`. Points with a non-finite coordinate are dropped. Returns the
   * number stored.
   */
  append(points: Float32Array, count: number, from = 0): number {
    if (count <= 0) return 0;
    this.reserve(this.count + count);
    const start = this.count;
    const pos = this.positions;
    const b = this.bounds;
    let n = start;
    for (let i = from; i < from + count; i++) {
      const x = points[i * CLOUD_FLOATS_PER_POINT]!;
      const y = points[i * CLOUD_FLOATS_PER_POINT + 1]!;
      const z = points[i * CLOUD_FLOATS_PER_POINT + 2]!;
      if (!Number.isFinite(x) || !Number.isFinite(y) || !Number.isFinite(z)) continue;
      pos[3 * n] = x;
      pos[3 * n + 1] = y;
      pos[3 * n + 2] = z;
      if (x < b.minX) b.minX = x;
      if (x > b.maxX) b.maxX = x;
      if (y < b.minY) b.minY = y;
      if (y > b.maxY) b.maxY = y;
      if (z < b.minZ) b.minZ = z;
      if (z > b.maxZ) b.maxZ = z;
      n++;
    }
    this.count = n;
    if (n === start) return 0;
    const range = snappedHeightRange(b.minZ, b.maxZ);
    const previous = this.colorRange;
    if (!previous || previous.lowM !== range.lowM || previous.highM !== range.highM) {
      // The scale widened: every point's colour changes.
      this.colorRange = range;
      this.colorVersion++;
      this.recolor(0, n);
    } else {
      this.recolor(start, n);
    }
    return n - start;
  }

  private recolor(from: number, to: number): void {
    const range = this.colorRange;
    if (!range) return;
    for (let i = from; i < to; i++) heightColor(this.positions[3 * i + 2]!, range, this.colors, 3 * i);
  }
}

/** Floor texture colours (little-endian RGBA u32): walls light and opaque, free floor dark and see-through, unknown clear. */
const FLOOR_WALL = packRgba(203, 213, 225, 255);
const FLOOR_FREE = packRgba(30, 41, 59, 150);
const FLOOR_UNKNOWN = 0;

function packRgba(r: number, g: number, b: number, a: number): number {
  return ((a << 24) | (b << 16) | (g << 8) | r) >>> 0;
}

/**
 * Paints an occupancy grid (0..100 %, else unknown) as the 3D view's floor: the map's walls are
 * what places the cloud in the building. Pixel i = cell i (row 0 = the bottom row).
 */
export function paintFloor(cells: Uint8Array, pixels: Uint32Array): void {
  for (let i = 0; i < cells.length; i++) {
    const v = cells[i]!;
    pixels[i] = v > 100 ? FLOOR_UNKNOWN : v >= 65 ? FLOOR_WALL : FLOOR_FREE;
  }
}
