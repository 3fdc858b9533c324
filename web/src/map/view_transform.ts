// The 2D view transform of the map canvas: map frame (metres, y up) <-> screen (CSS pixels, y down).
// Pure, so pan / zoom-about-the-cursor / fit are unit-tested without a browser.

export interface Bounds {
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

export const MIN_SCALE = 2; // px per metre
export const MAX_SCALE = 2000;

export class ViewTransform {
  /** Pixels per metre. */
  scale: number;
  /** Screen position of the map-frame origin. */
  originX: number;
  originY: number;

  constructor(scale = 40, originX = 0, originY = 0) {
    this.scale = scale;
    this.originX = originX;
    this.originY = originY;
  }

  clone(): ViewTransform {
    return new ViewTransform(this.scale, this.originX, this.originY);
  }

  toScreenX(x: number): number {
    return this.originX + x * this.scale;
  }

  toScreenY(y: number): number {
    return this.originY - y * this.scale;
  }

  toScreen(x: number, y: number): [number, number] {
    return [this.toScreenX(x), this.toScreenY(y)];
  }

  toWorld(sx: number, sy: number): [number, number] {
    return [(sx - this.originX) / this.scale, (this.originY - sy) / this.scale];
  }

  panBy(dx: number, dy: number): void {
    this.originX += dx;
    this.originY += dy;
  }

  /** Zooms by `factor`, keeping the world point under screen point (sx, sy) where it is. */
  zoomAbout(sx: number, sy: number, factor: number): void {
    const [wx, wy] = this.toWorld(sx, sy);
    this.scale = clamp(this.scale * factor, MIN_SCALE, MAX_SCALE);
    this.originX = sx - wx * this.scale;
    this.originY = sy + wy * this.scale;
  }

  /** Shows `bounds` centred in a width x height viewport with `margin` pixels left around it. */
  fit(bounds: Bounds, width: number, height: number, margin = 20): void {
    const bw = Math.max(bounds.maxX - bounds.minX, 1e-3);
    const bh = Math.max(bounds.maxY - bounds.minY, 1e-3);
    const availW = Math.max(width - 2 * margin, 1);
    const availH = Math.max(height - 2 * margin, 1);
    this.scale = clamp(Math.min(availW / bw, availH / bh), MIN_SCALE, MAX_SCALE);
    const cx = (bounds.minX + bounds.maxX) / 2;
    const cy = (bounds.minY + bounds.maxY) / 2;
    this.originX = width / 2 - cx * this.scale;
    this.originY = height / 2 + cy * this.scale;
  }

  /** Canvas 2D matrix (a, b, c, d, e, f) that maps map-frame metres to device pixels. */
  matrix(devicePixelRatio = 1): [number, number, number, number, number, number] {
    const s = this.scale * devicePixelRatio;
    return [s, 0, 0, -s, this.originX * devicePixelRatio, this.originY * devicePixelRatio];
  }
}

export function clamp(value: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, value));
}

/** `b` with `margin` metres added on every side. */
export function grow(b: Bounds, margin: number): Bounds {
  return { minX: b.minX - margin, minY: b.minY - margin, maxX: b.maxX + margin, maxY: b.maxY + margin };
}

export function boundsOf(points: Iterable<[number, number]>): Bounds | null {
  let b: Bounds | null = null;
  for (const [x, y] of points) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
    if (!b) b = { minX: x, minY: y, maxX: x, maxY: y };
    else {
      b.minX = Math.min(b.minX, x);
      b.minY = Math.min(b.minY, y);
      b.maxX = Math.max(b.maxX, x);
      b.maxY = Math.max(b.maxY, y);
    }
  }
  return b;
}

/** Wheel delta (pixels or lines) -> multiplicative zoom factor, smooth for trackpads. */
export function wheelZoomFactor(deltaY: number, deltaMode = 0): number {
  const pixels = deltaMode === 1 ? deltaY * 16 : deltaMode === 2 ? deltaY * 400 : deltaY;
  return Math.exp(-clamp(pixels, -300, 300) * 0.0015);
}
