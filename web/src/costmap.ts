// Costmaps (topics `costmap`, the global one, and `local_costmap`, the rolling window around the
// robot; binary topic id 4, README "Binary frames"): costs as ROS costmap_2d has them, the decoders
// of both encodings, the cost classes and the colours the map overlay and its legend share.
// Pure (no DOM), unit-tested.

import { FrameError } from './frame_error';
import type { JsonPose, Pose2D } from './frames';

export type CostmapWhich = 'global' | 'local';

export interface Costmap {
  which: CostmapWhich;
  width: number;
  height: number;
  /** m per cell. */
  resolution: number;
  /** Cell (0, 0)'s lower-left corner, map frame. */
  origin: Pose2D;
  /** Row-major, row 0 at the bottom: 0 free, 1..252 inflated, 253 inscribed, 254 lethal, 255 unknown. */
  costs: Uint8Array;
}

export const COST_FREE = 0;
export const COST_INFLATED_MAX = 252;
export const COST_INSCRIBED = 253;
export const COST_LETHAL = 254;
export const COST_UNKNOWN = 255;

export const COSTMAP_BODY_HEADER_BYTES = 32;
const WHICH: Record<number, CostmapWhich> = { 0: 'global', 1: 'local' };

/** The costmap body at `bodyOffset`: it must hold exactly width x height costs. */
export function decodeCostmapBody(buffer: ArrayBuffer, bodyOffset: number): Costmap {
  if (buffer.byteLength < bodyOffset + COSTMAP_BODY_HEADER_BYTES) throw new FrameError('costmap body too short');
  const view = new DataView(buffer, bodyOffset);
  const width = view.getUint32(0, true);
  const height = view.getUint32(4, true);
  const which = WHICH[view.getUint32(24, true)];
  if (!which) throw new FrameError(`bad costmap 'which' ${view.getUint32(24, true)}`);
  const cells = width * height;
  const bytes = buffer.byteLength - bodyOffset - COSTMAP_BODY_HEADER_BYTES;
  if (bytes !== cells) throw new FrameError(`costmap body holds ${bytes} costs, ${width}x${height} needs ${cells}`);
  return {
    which,
    width,
    height,
    resolution: view.getFloat32(8, true),
    origin: { x: view.getFloat32(12, true), y: view.getFloat32(16, true), theta: view.getFloat32(20, true) },
    costs: new Uint8Array(buffer, bodyOffset + COSTMAP_BODY_HEADER_BYTES, cells),
  };
}

export interface JsonCostmap {
  which: string;
  width: number;
  height: number;
  resolution: number;
  origin: JsonPose;
  data: number[];
}

/** The JSON form; a cost outside 0..255 (or -1, as some writers put unknown) is unknown. */
export function costmapFromJson(data: JsonCostmap): Costmap {
  if (data.which !== 'global' && data.which !== 'local') throw new FrameError(`bad costmap 'which' ${String(data.which)}`);
  const cells = data.width * data.height;
  const rows = Array.isArray(data.data) ? data.data : [];
  if (rows.length !== cells) throw new FrameError(`costmap JSON holds ${rows.length} costs, ${data.width}x${data.height} needs ${cells}`);
  const costs = new Uint8Array(cells);
  for (let i = 0; i < cells; i++) {
    const v = rows[i];
    costs[i] = typeof v === 'number' && v >= 0 && v <= 255 ? Math.round(v) : COST_UNKNOWN;
  }
  return {
    which: data.which,
    width: data.width,
    height: data.height,
    resolution: data.resolution,
    origin: { x: data.origin.x, y: data.origin.y, theta: data.origin.theta ?? 0 },
    costs,
  };
}

export type CostClass = 'free' | 'inflated' | 'inscribed' | 'lethal' | 'unknown';

export function costClass(cost: number): CostClass {
  if (cost === COST_FREE) return 'free';
  if (cost <= COST_INFLATED_MAX) return 'inflated';
  if (cost === COST_INSCRIBED) return 'inscribed';
  if (cost === COST_LETHAL) return 'lethal';
  return 'unknown';
}

/** Cells per class. */
export function countCosts(costmap: Pick<Costmap, 'costs'>): Record<CostClass, number> {
  const counts: Record<CostClass, number> = { free: 0, inflated: 0, inscribed: 0, lethal: 0, unknown: 0 };
  for (const v of costmap.costs) counts[costClass(v)]++;
  return counts;
}

// ---- colours (overlay and legend) ----

export type Rgba = readonly [number, number, number, number];

/** Free cells: a faint tint, so the window of the local costmap shows. */
export const FREE_RGBA: Rgba = [34, 197, 94, 0.1];
/** Inflated costs run from the first (cost 1) to the second (cost 252) colour. */
export const INFLATED_LOW_RGBA: Rgba = [250, 204, 21, 0.25];
export const INFLATED_HIGH_RGBA: Rgba = [249, 115, 22, 0.7];
export const INSCRIBED_RGBA: Rgba = [217, 70, 239, 0.8];
export const LETHAL_RGBA: Rgba = [239, 68, 68, 0.9];
export const UNKNOWN_RGBA: Rgba = [100, 116, 139, 0.3];

/** The colour of a cost (alpha 0..1). */
export function costColor(cost: number): Rgba {
  switch (costClass(cost)) {
    case 'free':
      return FREE_RGBA;
    case 'inscribed':
      return INSCRIBED_RGBA;
    case 'lethal':
      return LETHAL_RGBA;
    case 'unknown':
      return UNKNOWN_RGBA;
    case 'inflated': {
      const k = (cost - 1) / (COST_INFLATED_MAX - 1);
      const mix = (i: number) => INFLATED_LOW_RGBA[i]! + (INFLATED_HIGH_RGBA[i]! - INFLATED_LOW_RGBA[i]!) * k;
      return [Math.round(mix(0)), Math.round(mix(1)), Math.round(mix(2)), mix(3)];
    }
  }
}

export function cssColor([r, g, b, a]: Rgba): string {
  return `rgba(${r}, ${g}, ${b}, ${a})`;
}

/** The inflated gradient as CSS, for the legend. */
export function inflatedGradientCss(): string {
  return `linear-gradient(90deg, ${cssColor(INFLATED_LOW_RGBA)}, ${cssColor(INFLATED_HIGH_RGBA)})`;
}

/** 256-entry lookup from cost to RGBA packed as a little-endian u32 (ImageData byte order). */
function buildPalette(): Uint32Array {
  const lut = new Uint32Array(256);
  for (let v = 0; v < 256; v++) {
    const [r, g, b, a] = costColor(v);
    lut[v] = ((Math.round(a * 255) << 24) | (b << 16) | (g << 8) | r) >>> 0;
  }
  return lut;
}

export const COST_PALETTE = buildPalette();

/** Paints the costs into RGBA pixels, image row r = costmap row r (the view transform flips it). */
export function paintCosts(costmap: Pick<Costmap, 'costs'>, pixels: Uint32Array): void {
  const n = Math.min(costmap.costs.length, pixels.length);
  for (let i = 0; i < n; i++) pixels[i] = COST_PALETTE[costmap.costs[i]!]!;
}
