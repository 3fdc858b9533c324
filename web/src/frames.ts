// Decoders for the stream's binary frames (README "Binary frames") and the equivalent JSON bodies.
// Pure functions: no DOM, no sockets, so they are unit-tested in Node. The map's tile frames, the
// costmaps and the particle cloud have their own modules (tiles.ts, costmap.ts, particles.ts);
// decodeBinaryFrame dispatches to them.

import { decodeCostmapBody } from './costmap';
import type { Costmap } from './costmap';
import { FrameError } from './frame_error';
import { decodeParticlesBody } from './particles';
import type { ParticleSet } from './particles';
import { decodeTileBody, MAP_FLAG_TILES } from './tiles';
import type { TileUpdate } from './tiles';

export { FrameError };

export const BINARY_MAGIC = 'MBT1';
export const MIN_HEADER_BYTES = 32;

export const BinaryTopic = {
  scan: 1,
  map: 2,
  cloud: 3,
  costmap: 4,
  camera: 5,
  particles: 6,
} as const;

const BINARY_TOPIC_NAMES: Record<number, string> = {
  1: 'scan',
  2: 'map',
  3: 'cloud',
  4: 'costmap',
  5: 'camera',
  6: 'particles',
};

export interface FrameHeader {
  topicId: number;
  topic: string;
  headerBytes: number;
  seq: number;
  t: number;
  wallUs: number;
}

export interface Pose2D {
  x: number;
  y: number;
  theta: number;
}

export interface LaserScan {
  angleMin: number;
  angleIncrement: number;
  rangeMin: number;
  rangeMax: number;
  sensorPose: Pose2D;
  ranges: Float32Array;
}

/** Occupancy grid; cells are 0..100 occupancy percent or UNKNOWN_CELL, row 0 at the bottom. */
export interface MapGrid {
  id: number;
  width: number;
  height: number;
  resolution: number;
  origin: Pose2D;
  cells: Uint8Array;
}

export const UNKNOWN_CELL = 255;

/**
 * One chunk of a 3D sweep's point cloud (topic 3, README "Binary frames"): the points of one
 * tilting-laser scan, in the map frame. `points` holds x, y, z (m) and intensity (0..1) per point.
 */
export interface CloudChunk {
  sweepId: number;
  /** Index of this chunk's first point within the sweep. */
  first: number;
  count: number;
  /** The sweep's last chunk: the sweep is done. */
  last: boolean;
  scansDone: number;
  scansTotal: number;
  /** 4 floats per point: x, y, z (m, map frame), intensity (0..1). */
  points: Float32Array;
}

export const CLOUD_BODY_HEADER_BYTES = 32;
export const CLOUD_FLOATS_PER_POINT = 4;
const CLOUD_FLAG_LAST = 1;

export function parseHeader(buffer: ArrayBuffer): FrameHeader {
  if (buffer.byteLength < MIN_HEADER_BYTES) {
    throw new FrameError(`binary frame too short (${buffer.byteLength} bytes)`);
  }
  const view = new DataView(buffer);
  const magic = String.fromCharCode(
    view.getUint8(0),
    view.getUint8(1),
    view.getUint8(2),
    view.getUint8(3),
  );
  if (magic !== BINARY_MAGIC) throw new FrameError(`bad magic '${magic}'`);
  const topicId = view.getUint16(4, true);
  const headerBytes = view.getUint16(6, true);
  if (headerBytes < MIN_HEADER_BYTES || headerBytes > buffer.byteLength) {
    throw new FrameError(`bad header_bytes ${headerBytes}`);
  }
  return {
    topicId,
    topic: BINARY_TOPIC_NAMES[topicId] ?? `binary_${topicId}`,
    headerBytes,
    seq: Number(view.getBigUint64(8, true)),
    t: view.getFloat64(16, true),
    wallUs: Number(view.getBigInt64(24, true)),
  };
}

/** A Float32Array over `count` floats at `offset`, without copying when the offset is aligned. */
function float32s(buffer: ArrayBuffer, offset: number, count: number): Float32Array {
  if (offset % 4 === 0) return new Float32Array(buffer, offset, count);
  return new Float32Array(buffer.slice(offset, offset + count * 4));
}

export function decodeScanBody(buffer: ArrayBuffer, bodyOffset: number): LaserScan {
  if (buffer.byteLength < bodyOffset + 32) throw new FrameError('scan body too short');
  const view = new DataView(buffer, bodyOffset);
  const count = view.getUint32(28, true);
  if (buffer.byteLength < bodyOffset + 32 + count * 4) {
    throw new FrameError(`scan body holds fewer than ${count} ranges`);
  }
  return {
    angleMin: view.getFloat32(0, true),
    angleIncrement: view.getFloat32(4, true),
    rangeMin: view.getFloat32(8, true),
    rangeMax: view.getFloat32(12, true),
    sensorPose: {
      x: view.getFloat32(16, true),
      y: view.getFloat32(20, true),
      theta: view.getFloat32(24, true),
    },
    ranges: float32s(buffer, bodyOffset + 32, count),
  };
}

export function decodeMapBody(buffer: ArrayBuffer, bodyOffset: number): MapGrid {
  if (buffer.byteLength < bodyOffset + 32) throw new FrameError('map body too short');
  const view = new DataView(buffer, bodyOffset);
  const width = view.getUint32(0, true);
  const height = view.getUint32(4, true);
  const cellCount = width * height;
  if (buffer.byteLength < bodyOffset + 32 + cellCount) {
    throw new FrameError(`map body holds fewer than ${width}x${height} cells`);
  }
  return {
    width,
    height,
    resolution: view.getFloat32(8, true),
    origin: {
      x: view.getFloat32(12, true),
      y: view.getFloat32(16, true),
      theta: view.getFloat32(20, true),
    },
    id: view.getUint32(24, true),
    cells: new Uint8Array(buffer, bodyOffset + 32, cellCount),
  };
}

/**
 * The cloud body at `bodyOffset`. The body must hold exactly `count` points: a shorter one is a
 * truncated frame, a longer one disagrees with its count; either way the points cannot be trusted.
 */
export function decodeCloudBody(buffer: ArrayBuffer, bodyOffset: number): CloudChunk {
  if (buffer.byteLength < bodyOffset + CLOUD_BODY_HEADER_BYTES) throw new FrameError('cloud body too short');
  const view = new DataView(buffer, bodyOffset);
  const count = view.getUint32(8, true);
  const pointBytes = buffer.byteLength - bodyOffset - CLOUD_BODY_HEADER_BYTES;
  const expectedBytes = count * CLOUD_FLOATS_PER_POINT * 4;
  if (pointBytes < expectedBytes) throw new FrameError(`cloud body holds fewer than ${count} points`);
  if (pointBytes !== expectedBytes) {
    throw new FrameError(`cloud body holds ${pointBytes} point bytes, count ${count} says ${expectedBytes}`);
  }
  return {
    sweepId: view.getUint32(0, true),
    first: view.getUint32(4, true),
    count,
    last: (view.getUint32(12, true) & CLOUD_FLAG_LAST) !== 0,
    scansDone: view.getUint32(16, true),
    scansTotal: view.getUint32(20, true),
    points: float32s(buffer, bodyOffset + CLOUD_BODY_HEADER_BYTES, count * CLOUD_FLOATS_PER_POINT),
  };
}

/**
 * The camera body (topic 5): one JPEG file, the whole rest of the message. A view, not a copy; a
 * body that does not start with the JPEG start-of-image marker (FF D8) is refused.
 */
export function decodeCameraBody(buffer: ArrayBuffer, bodyOffset: number): Uint8Array {
  const jpeg = new Uint8Array(buffer, bodyOffset);
  if (jpeg.length < 4) throw new FrameError(`camera body too short (${jpeg.length} bytes)`);
  if (jpeg[0] !== 0xff || jpeg[1] !== 0xd8) throw new FrameError('camera body is not a JPEG (no FF D8 start)');
  return jpeg;
}

/** The flags of a map body (offset 28; bit 0: a tile frame). Zero for a body too short to hold them. */
export function mapBodyFlags(buffer: ArrayBuffer, bodyOffset: number): number {
  if (buffer.byteLength < bodyOffset + 32) return 0;
  return new DataView(buffer, bodyOffset).getUint32(28, true);
}

export type BinaryFrame =
  | { header: FrameHeader; kind: 'scan'; scan: LaserScan }
  | { header: FrameHeader; kind: 'map'; map: MapGrid }
  | { header: FrameHeader; kind: 'tiles'; tiles: TileUpdate }
  | { header: FrameHeader; kind: 'cloud'; cloud: CloudChunk }
  | { header: FrameHeader; kind: 'costmap'; costmap: Costmap }
  | { header: FrameHeader; kind: 'particles'; particles: ParticleSet }
  | { header: FrameHeader; kind: 'camera'; jpeg: Uint8Array }
  | { header: FrameHeader; kind: 'other' };

export function decodeBinaryFrame(buffer: ArrayBuffer): BinaryFrame {
  const header = parseHeader(buffer);
  switch (header.topicId) {
    case BinaryTopic.scan:
      return { header, kind: 'scan', scan: decodeScanBody(buffer, header.headerBytes) };
    case BinaryTopic.map:
      // Bit 0 of the flags: changed tiles of the map being built, not a whole map.
      if ((mapBodyFlags(buffer, header.headerBytes) & MAP_FLAG_TILES) !== 0) {
        return { header, kind: 'tiles', tiles: decodeTileBody(buffer, header.headerBytes) };
      }
      return { header, kind: 'map', map: decodeMapBody(buffer, header.headerBytes) };
    case BinaryTopic.cloud:
      return { header, kind: 'cloud', cloud: decodeCloudBody(buffer, header.headerBytes) };
    case BinaryTopic.costmap:
      return { header, kind: 'costmap', costmap: decodeCostmapBody(buffer, header.headerBytes) };
    case BinaryTopic.particles:
      return { header, kind: 'particles', particles: decodeParticlesBody(buffer, header.headerBytes) };
    case BinaryTopic.camera:
      return { header, kind: 'camera', jpeg: decodeCameraBody(buffer, header.headerBytes) };
    default:
      return { header, kind: 'other' };
  }
}

// ---- JSON bodies (the same data with "encoding":"json") ----

export interface JsonPose {
  x: number;
  y: number;
  theta: number;
}

export interface JsonScan {
  angle_min: number;
  angle_increment: number;
  range_min: number;
  range_max: number;
  ranges: (number | null)[];
  sensor_pose: JsonPose;
}

export interface JsonMap {
  id: number;
  width: number;
  height: number;
  resolution: number;
  origin: JsonPose;
  data: number[];
}

export interface JsonCloud {
  sweep_id: number;
  first: number;
  count: number;
  last: boolean;
  scans_done: number;
  scans_total: number;
  points: number[][];
}

/** The `camera` topic as JSON ("encoding":"json"). */
export interface JsonCamera {
  width: number;
  height: number;
  encoding: string;
  data_base64: string;
}

/** The JPEG bytes of a JSON camera frame. */
export function cameraFromJson(data: JsonCamera): Uint8Array {
  if (data.encoding !== 'jpeg') throw new FrameError(`camera encoding ${String(data.encoding)} is not jpeg`);
  if (typeof data.data_base64 !== 'string') throw new FrameError('camera frame without data_base64');
  let binary: string;
  try {
    binary = atob(data.data_base64);
  } catch {
    throw new FrameError('camera data_base64 is not base64');
  }
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return decodeCameraBody(bytes.buffer, 0);
}

export function cloudFromJson(data: JsonCloud): CloudChunk {
  const rows = Array.isArray(data.points) ? data.points : [];
  if (rows.length !== data.count) throw new FrameError(`cloud JSON holds ${rows.length} points, count says ${data.count}`);
  const points = new Float32Array(rows.length * CLOUD_FLOATS_PER_POINT);
  rows.forEach((row, i) => {
    for (let k = 0; k < CLOUD_FLOATS_PER_POINT; k++) {
      const v = row[k];
      // JSON has no NaN (nlohmann writes null): such a point is dropped by the consumers.
      points[i * CLOUD_FLOATS_PER_POINT + k] = typeof v === 'number' ? v : NaN;
    }
  });
  return {
    sweepId: data.sweep_id,
    first: data.first,
    count: rows.length,
    last: !!data.last,
    scansDone: data.scans_done,
    scansTotal: data.scans_total,
    points,
  };
}

export function scanFromJson(data: JsonScan): LaserScan {
  // JSON cannot carry NaN/Inf: nlohmann writes null, which becomes "no return".
  const ranges = Float32Array.from(data.ranges, (r) => (typeof r === 'number' ? r : NaN));
  return {
    angleMin: data.angle_min,
    angleIncrement: data.angle_increment,
    rangeMin: data.range_min,
    rangeMax: data.range_max,
    sensorPose: { x: data.sensor_pose.x, y: data.sensor_pose.y, theta: data.sensor_pose.theta },
    ranges,
  };
}

export function mapFromJson(data: JsonMap): MapGrid {
  const cells = new Uint8Array(data.width * data.height);
  for (let i = 0; i < cells.length; i++) {
    const v = data.data[i];
    cells[i] = v === undefined || v < 0 || v > 100 ? UNKNOWN_CELL : v;
  }
  return {
    id: data.id,
    width: data.width,
    height: data.height,
    resolution: data.resolution,
    origin: { x: data.origin.x, y: data.origin.y, theta: data.origin.theta },
    cells,
  };
}

// ---- Derived geometry ----

/** Whether a range is a return: inside [range_min, range_max] (NaN and Inf are not). */
export function isReturn(range: number, rangeMin: number, rangeMax: number): boolean {
  return range >= rangeMin && range <= rangeMax;
}

/**
 * Map-frame end points of the scan's returns, packed as [x0, y0, x1, y1, ...] into `out`
 * (grown when too small). Returns the number of points written.
 */
export function scanEndpoints(scan: LaserScan, out: Float32Array): { points: Float32Array; count: number } {
  const n = scan.ranges.length;
  const points = out.length >= 2 * n ? out : new Float32Array(2 * n);
  let count = 0;
  const { x, y, theta } = scan.sensorPose;
  for (let i = 0; i < n; i++) {
    const r = scan.ranges[i]!;
    if (!isReturn(r, scan.rangeMin, scan.rangeMax)) continue;
    const a = theta + scan.angleMin + i * scan.angleIncrement;
    points[2 * count] = x + r * Math.cos(a);
    points[2 * count + 1] = y + r * Math.sin(a);
    count++;
  }
  return { points, count };
}

/** Map-frame corners (x, y pairs) of the grid, honouring a rotated origin. */
export function mapCorners(map: MapGrid): [number, number][] {
  const w = map.width * map.resolution;
  const h = map.height * map.resolution;
  const c = Math.cos(map.origin.theta);
  const s = Math.sin(map.origin.theta);
  const local: [number, number][] = [
    [0, 0],
    [w, 0],
    [w, h],
    [0, h],
  ];
  return local.map(([lx, ly]) => [map.origin.x + c * lx - s * ly, map.origin.y + s * lx + c * ly]);
}
