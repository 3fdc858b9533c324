import { describe, expect, it } from 'vitest';
import {
  cameraFromJson,
  cloudFromJson,
  decodeBinaryFrame,
  FrameError,
  isReturn,
  mapCorners,
  mapFromJson,
  parseHeader,
  scanEndpoints,
  scanFromJson,
  UNKNOWN_CELL,
} from '../src/frames';

/** Writes a frame the way api/frame_codec.cpp does (header_bytes may be larger than 32). */
function frame(topicId: number, body: ArrayBuffer, opts: { seq?: number; t?: number; wallUs?: number; headerBytes?: number } = {}): ArrayBuffer {
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

function scanBody(ranges: number[], pose = { x: 1, y: 2, theta: Math.PI / 2 }): ArrayBuffer {
  const body = new ArrayBuffer(32 + ranges.length * 4);
  const view = new DataView(body);
  view.setFloat32(0, -Math.PI / 2, true);
  view.setFloat32(4, Math.PI / 2, true);
  view.setFloat32(8, 0.1, true);
  view.setFloat32(12, 10, true);
  view.setFloat32(16, pose.x, true);
  view.setFloat32(20, pose.y, true);
  view.setFloat32(24, pose.theta, true);
  view.setUint32(28, ranges.length, true);
  ranges.forEach((r, i) => view.setFloat32(32 + 4 * i, r, true));
  return body;
}

function mapBody(width: number, height: number, cells: number[], id = 7): ArrayBuffer {
  const body = new ArrayBuffer(32 + width * height);
  const view = new DataView(body);
  view.setUint32(0, width, true);
  view.setUint32(4, height, true);
  view.setFloat32(8, 0.05, true);
  view.setFloat32(12, -1.5, true);
  view.setFloat32(16, -2.5, true);
  view.setFloat32(20, 0, true);
  view.setUint32(24, id, true);
  view.setUint32(28, 0, true);
  new Uint8Array(body, 32).set(cells);
  return body;
}

/** A cloud body (topic 3): 32-byte sub-header, then x, y, z, intensity per point. */
function cloudBody(
  points: number[][],
  opts: { sweepId?: number; first?: number; count?: number; flags?: number; scansDone?: number; scansTotal?: number } = {},
): ArrayBuffer {
  const body = new ArrayBuffer(32 + points.length * 16);
  const view = new DataView(body);
  view.setUint32(0, opts.sweepId ?? 9, true);
  view.setUint32(4, opts.first ?? 0, true);
  view.setUint32(8, opts.count ?? points.length, true);
  view.setUint32(12, opts.flags ?? 0, true);
  view.setUint32(16, opts.scansDone ?? 1, true);
  view.setUint32(20, opts.scansTotal ?? 24, true);
  points.forEach((p, i) => p.forEach((v, k) => view.setFloat32(32 + 16 * i + 4 * k, v, true)));
  return body;
}

describe('binary header', () => {
  it('reads magic, topic, seq, t and wall_us', () => {
    const h = parseHeader(frame(1, scanBody([1]), { seq: 42, t: 12.5, wallUs: 1_700_000_000_123_456 }));
    expect(h).toEqual({ topicId: 1, topic: 'scan', headerBytes: 32, seq: 42, t: 12.5, wallUs: 1_700_000_000_123_456 });
  });

  it('rejects a bad magic and short frames', () => {
    const buffer = frame(1, scanBody([1]));
    new DataView(buffer).setUint8(0, 'X'.charCodeAt(0));
    expect(() => parseHeader(buffer)).toThrow(FrameError);
    expect(() => parseHeader(new ArrayBuffer(10))).toThrow(FrameError);
  });

  it('rejects a header_bytes beyond the frame', () => {
    const buffer = frame(1, new ArrayBuffer(0));
    new DataView(buffer).setUint16(6, 64, true);
    expect(() => parseHeader(buffer)).toThrow(FrameError);
  });
});

describe('scan frames', () => {
  it('decodes the body with a Float32Array view over the ranges', () => {
    const decoded = decodeBinaryFrame(frame(1, scanBody([1, 2, 3]), { seq: 3 }));
    expect(decoded.kind).toBe('scan');
    if (decoded.kind !== 'scan') return;
    const scan = decoded.scan;
    expect(scan.angleMin).toBeCloseTo(-Math.PI / 2, 6);
    expect(scan.angleIncrement).toBeCloseTo(Math.PI / 2, 6);
    expect(scan.rangeMin).toBeCloseTo(0.1, 6);
    expect(scan.rangeMax).toBe(10);
    expect(scan.sensorPose.x).toBe(1);
    expect(scan.sensorPose.y).toBe(2);
    expect(Array.from(scan.ranges)).toEqual([1, 2, 3]);
    expect(scan.ranges.buffer.byteLength).toBeGreaterThan(scan.ranges.byteLength); // a view, not a copy
  });

  it('honours a header grown beyond 32 bytes', () => {
    const decoded = decodeBinaryFrame(frame(1, scanBody([4, 5]), { headerBytes: 48 }));
    expect(decoded.header.headerBytes).toBe(48);
    if (decoded.kind !== 'scan') throw new Error('not a scan');
    expect(Array.from(decoded.scan.ranges)).toEqual([4, 5]);
  });

  it('copies when the body is not 4-byte aligned', () => {
    const decoded = decodeBinaryFrame(frame(1, scanBody([6, 7]), { headerBytes: 34 }));
    if (decoded.kind !== 'scan') throw new Error('not a scan');
    expect(Array.from(decoded.scan.ranges)).toEqual([6, 7]);
  });

  it('refuses a count larger than the frame', () => {
    const body = scanBody([1, 2]);
    new DataView(body).setUint32(28, 100, true);
    expect(() => decodeBinaryFrame(frame(1, body))).toThrow(FrameError);
  });

  it('puts end points in the map frame and skips non-returns', () => {
    // Sensor at (1, 2) facing +y; beams at -90°, 0°, +90° relative -> map +x, +y, -x.
    const decoded = decodeBinaryFrame(frame(1, scanBody([2, Infinity, 0.05, NaN, 3].slice(0, 3))));
    if (decoded.kind !== 'scan') throw new Error('not a scan');
    const { points, count } = scanEndpoints(decoded.scan, new Float32Array(0));
    expect(count).toBe(1); // Inf and 0.05 (< range_min) are no return
    expect(points[0]).toBeCloseTo(3, 5);
    expect(points[1]).toBeCloseTo(2, 5);
    expect(isReturn(10, 0.1, 10)).toBe(true);
    expect(isReturn(10.01, 0.1, 10)).toBe(false);
    expect(isReturn(NaN, 0.1, 10)).toBe(false);
  });

  it('decodes the JSON encoding to the same shape (null = no return)', () => {
    const scan = scanFromJson({
      angle_min: -1,
      angle_increment: 0.5,
      range_min: 0.1,
      range_max: 5,
      ranges: [1, null, 2],
      sensor_pose: { x: 0, y: 0, theta: 0 },
    });
    expect(scan.ranges.length).toBe(3);
    expect(Number.isNaN(scan.ranges[1])).toBe(true);
    expect(scanEndpoints(scan, new Float32Array(0)).count).toBe(2);
  });
});

describe('map frames', () => {
  it('decodes size, resolution, origin, id and cells (row 0 at the bottom)', () => {
    const decoded = decodeBinaryFrame(frame(2, mapBody(3, 2, [0, 100, 255, 50, 0, 0])));
    expect(decoded.kind).toBe('map');
    if (decoded.kind !== 'map') return;
    const map = decoded.map;
    expect(map.width).toBe(3);
    expect(map.height).toBe(2);
    expect(map.resolution).toBeCloseTo(0.05, 6);
    expect(map.origin).toEqual({ x: -1.5, y: -2.5, theta: 0 });
    expect(map.id).toBe(7);
    expect(Array.from(map.cells)).toEqual([0, 100, 255, 50, 0, 0]);
  });

  it('refuses a map with fewer cells than width x height', () => {
    const body = mapBody(3, 2, [0, 0, 0, 0, 0, 0]);
    new DataView(body).setUint32(4, 50, true);
    expect(() => decodeBinaryFrame(frame(2, body))).toThrow(FrameError);
  });

  it('maps JSON -1 to unknown', () => {
    const map = mapFromJson({ id: 0, width: 2, height: 1, resolution: 0.1, origin: { x: 0, y: 0, theta: 0 }, data: [-1, 42] });
    expect(Array.from(map.cells)).toEqual([UNKNOWN_CELL, 42]);
  });

  it('computes the corners of a rotated grid', () => {
    const map = mapFromJson({ id: 0, width: 10, height: 20, resolution: 0.1, origin: { x: 1, y: 1, theta: Math.PI / 2 }, data: [] });
    const corners = mapCorners(map);
    expect(corners[1]![0]).toBeCloseTo(1, 9); // +x of the grid points along map +y
    expect(corners[1]![1]).toBeCloseTo(2, 9);
    expect(corners[3]![0]).toBeCloseTo(-1, 9);
    expect(corners[3]![1]).toBeCloseTo(1, 9);
  });

  it('leaves unknown topics to the caller', () => {
    expect(decodeBinaryFrame(frame(7, new ArrayBuffer(8))).kind).toBe('other');
  });
});

describe('cloud frames', () => {
  const points = [
    [1, 2, 0.5, 0.25],
    [-3, 4.5, 1.75, 1],
    [0, 0, -0.125, 0],
  ];

  it('decodes sweep id, first index, count, last flag, scans and the points (a view, not a copy)', () => {
    const decoded = decodeBinaryFrame(frame(3, cloudBody(points, { sweepId: 12, first: 721, flags: 1, scansDone: 24, scansTotal: 24 })));
    expect(decoded.kind).toBe('cloud');
    if (decoded.kind !== 'cloud') return;
    const c = decoded.cloud;
    expect(c).toMatchObject({ sweepId: 12, first: 721, count: 3, last: true, scansDone: 24, scansTotal: 24 });
    expect(Array.from(c.points)).toEqual(points.flat());
    expect(c.points.buffer.byteLength).toBeGreaterThan(c.points.byteLength);
  });

  it('reads the last flag from bit 0 only', () => {
    const running = decodeBinaryFrame(frame(3, cloudBody(points, { flags: 2 })));
    if (running.kind !== 'cloud') throw new Error('not a cloud');
    expect(running.cloud.last).toBe(false);
  });

  it('honours a header_bytes larger than 32 (aligned and not)', () => {
    for (const headerBytes of [40, 46]) {
      const decoded = decodeBinaryFrame(frame(3, cloudBody(points, { first: 5 }), { headerBytes }));
      expect(decoded.header.headerBytes).toBe(headerBytes);
      if (decoded.kind !== 'cloud') throw new Error('not a cloud');
      expect(decoded.cloud.first).toBe(5);
      expect(Array.from(decoded.cloud.points)).toEqual(points.flat());
    }
  });

  it('accepts an empty chunk', () => {
    const decoded = decodeBinaryFrame(frame(3, cloudBody([], { flags: 1 })));
    if (decoded.kind !== 'cloud') throw new Error('not a cloud');
    expect(decoded.cloud.count).toBe(0);
    expect(decoded.cloud.last).toBe(true);
  });

  it('rejects a truncated frame', () => {
    const whole = frame(3, cloudBody(points));
    expect(() => decodeBinaryFrame(whole.slice(0, whole.byteLength - 4))).toThrow(FrameError);
    expect(() => decodeBinaryFrame(whole.slice(0, 32 + 20))).toThrow(/cloud body too short/);
  });

  it('rejects a count that disagrees with the points in the body', () => {
    expect(() => decodeBinaryFrame(frame(3, cloudBody(points, { count: 4 })))).toThrow(/fewer than 4 points/);
    expect(() => decodeBinaryFrame(frame(3, cloudBody(points, { count: 2 })))).toThrow(/count 2/);
  });

  it('decodes the JSON encoding to the same shape and rejects a count mismatch', () => {
    const json = { sweep_id: 4, first: 10, count: 2, last: false, scans_done: 3, scans_total: 80, points: [[1, 2, 3, 0.5], [4, 5, null as unknown as number, 1]] };
    const c = cloudFromJson(json);
    expect(c).toMatchObject({ sweepId: 4, first: 10, count: 2, last: false, scansDone: 3, scansTotal: 80 });
    expect(Array.from(c.points.subarray(0, 4))).toEqual([1, 2, 3, 0.5]);
    expect(Number.isNaN(c.points[6])).toBe(true); // JSON null: no coordinate
    expect(() => cloudFromJson({ ...json, count: 3 })).toThrow(FrameError);
  });
});

describe('camera frames', () => {
  // The start and end of a JPEG file: SOI, an APP0 marker's first bytes, EOI.
  const jpeg = new Uint8Array([0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0xff, 0xd9]);

  it('decodes topic 5 as the JPEG that fills the rest of the message, after a longer header too', () => {
    for (const headerBytes of [32, 40]) {
      const decoded = decodeBinaryFrame(frame(5, jpeg.slice().buffer, { seq: 9, t: 3.5, headerBytes }));
      if (decoded.kind !== 'camera') throw new Error(`decoded as ${decoded.kind}`);
      expect(decoded.header.topic).toBe('camera');
      expect(decoded.header.seq).toBe(9);
      expect(Array.from(decoded.jpeg)).toEqual(Array.from(jpeg));
    }
  });

  it('rejects a body that is not a JPEG', () => {
    expect(() => decodeBinaryFrame(frame(5, new Uint8Array([0x89, 0x50, 0x4e, 0x47, 0, 0]).buffer))).toThrow(/not a JPEG/);
    expect(() => decodeBinaryFrame(frame(5, new Uint8Array([0xff]).buffer))).toThrow(/too short/);
  });

  it('decodes the JSON encoding (data_base64)', () => {
    const data_base64 = btoa(String.fromCharCode(...jpeg));
    expect(Array.from(cameraFromJson({ width: 640, height: 480, encoding: 'jpeg', data_base64 }))).toEqual(Array.from(jpeg));
    expect(() => cameraFromJson({ width: 640, height: 480, encoding: 'png', data_base64 })).toThrow(FrameError);
    expect(() => cameraFromJson({ width: 640, height: 480, encoding: 'jpeg', data_base64: '%%%' })).toThrow(FrameError);
  });
});
