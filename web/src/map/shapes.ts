// Drawing helpers shared by the layers, in CSS pixels unless said otherwise.

import type { Pose2D } from '../frames';
import type { ViewTransform } from './view_transform';

/** Map-frame points as [x0, y0, x1, y1, ...], the layout the polyline helper reads. */
export function packPoints<P>(points: readonly P[], x: (p: P) => number, y: (p: P) => number): Float64Array {
  const xy = new Float64Array(points.length * 2);
  points.forEach((p, i) => {
    xy[2 * i] = x(p);
    xy[2 * i + 1] = y(p);
  });
  return xy;
}

/** How to stroke a polyline. */
export interface LineStyle {
  color: string;
  width: number;
}

/** Which points of a buffer to draw: `count` from point `start`, wrapping after `ring` points (a ring buffer). */
export interface PointRange {
  count: number;
  start: number;
  ring: number;
}

/** Strokes the points of `xy` (map frame) in `range`, all of them by default. */
export function strokePolyline(
  ctx: CanvasRenderingContext2D,
  view: ViewTransform,
  xy: Float64Array,
  style: LineStyle,
  range: PointRange = { count: xy.length / 2, start: 0, ring: xy.length / 2 },
): void {
  const { count, start, ring } = range;
  if (count < 2) return;
  ctx.strokeStyle = style.color;
  ctx.lineWidth = style.width;
  ctx.lineJoin = 'round';
  ctx.beginPath();
  for (let k = 0; k < count; k++) {
    const i = (start + k) % ring;
    const sx = view.toScreenX(xy[2 * i]!);
    const sy = view.toScreenY(xy[2 * i + 1]!);
    if (k === 0) ctx.moveTo(sx, sy);
    else ctx.lineTo(sx, sy);
  }
  ctx.stroke();
}

/** An arrow from (sx, sy) along the map-frame angle `theta`, `length` pixels long. */
export function drawArrow(
  ctx: CanvasRenderingContext2D,
  sx: number,
  sy: number,
  theta: number,
  length: number,
  style: LineStyle,
): void {
  const ux = Math.cos(theta);
  const uy = -Math.sin(theta); // screen y is down
  const ex = sx + ux * length;
  const ey = sy + uy * length;
  const head = Math.min(12, 4 + length * 0.25);
  ctx.strokeStyle = style.color;
  ctx.fillStyle = style.color;
  ctx.lineWidth = style.width;
  ctx.lineCap = 'round';
  ctx.beginPath();
  ctx.moveTo(sx, sy);
  ctx.lineTo(ex - ux * head * 0.6, ey - uy * head * 0.6);
  ctx.stroke();
  ctx.lineCap = 'butt';
  ctx.beginPath();
  ctx.moveTo(ex, ey);
  ctx.lineTo(ex - ux * head - uy * head * 0.5, ey - uy * head + ux * head * 0.5);
  ctx.lineTo(ex - ux * head + uy * head * 0.5, ey - uy * head - ux * head * 0.5);
  ctx.closePath();
  ctx.fill();
}

/** An X of half-size k screen pixels at (sx, sy), in the current stroke style. */
export function strokeCross(ctx: CanvasRenderingContext2D, sx: number, sy: number, k: number): void {
  ctx.beginPath();
  ctx.moveTo(sx - k, sy - k);
  ctx.lineTo(sx + k, sy + k);
  ctx.moveTo(sx + k, sy - k);
  ctx.lineTo(sx - k, sy + k);
  ctx.stroke();
}

/**
 * Draws a pre-painted grid image whose pixel (0, 0) corner sits at `origin` (map frame, rotated
 * by origin.theta), `metresPerPixel` on a side. Unsmoothed: cells stay crisp squares when zoomed.
 */
export function drawGridImage(
  ctx: CanvasRenderingContext2D,
  view: ViewTransform,
  dpr: number,
  image: CanvasImageSource,
  origin: Pose2D,
  metresPerPixel: number,
): void {
  ctx.setTransform(...view.matrix(dpr));
  ctx.translate(origin.x, origin.y);
  ctx.rotate(origin.theta);
  ctx.scale(metresPerPixel, metresPerPixel);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(image, 0, 0);
  ctx.imageSmoothingEnabled = true;
}

/** A canvas of `width` x `height` pixels filled by `paint` (RGBA as little-endian u32), or null without 2D. */
export function paintedCanvas(width: number, height: number, paint: (pixels: Uint32Array) => void): HTMLCanvasElement | null {
  const image = document.createElement('canvas');
  image.width = width;
  image.height = height;
  const ctx = image.getContext('2d');
  if (!ctx) return null;
  const data = ctx.createImageData(width, height);
  paint(new Uint32Array(data.data.buffer));
  ctx.putImageData(data, 0, 0);
  return image;
}

/**
 * An offscreen canvas painted pixel by pixel and repainted in place: the canvas and its ImageData
 * are kept while the size stays (a costmap at 5 Hz allocates nothing per frame).
 */
export class PixelCanvas {
  canvas: HTMLCanvasElement | null = null;
  private image: ImageData | null = null;

  /** Paints all pixels; false without 2D. */
  paint(width: number, height: number, paint: (pixels: Uint32Array) => void): boolean {
    if (width <= 0 || height <= 0) return false;
    if (!this.canvas || this.canvas.width !== width || this.canvas.height !== height || !this.image) {
      this.canvas = document.createElement('canvas');
      this.canvas.width = width;
      this.canvas.height = height;
      this.image = this.canvas.getContext('2d')?.createImageData(width, height) ?? null;
    }
    const ctx = this.canvas.getContext('2d');
    if (!ctx || !this.image) return false;
    const pixels = new Uint32Array(this.image.data.buffer);
    pixels.fill(0);
    paint(pixels);
    ctx.putImageData(this.image, 0, 0);
    return true;
  }
}

/** Traces a closed polygon (map frame) as a screen path; call fill / stroke / clip after. */
export function tracePolygon(ctx: CanvasRenderingContext2D, view: ViewTransform, points: readonly (readonly [number, number])[]): void {
  ctx.beginPath();
  points.forEach(([x, y], i) => {
    const sx = view.toScreenX(x);
    const sy = view.toScreenY(y);
    if (i === 0) ctx.moveTo(sx, sy);
    else ctx.lineTo(sx, sy);
  });
  ctx.closePath();
}

/**
 * Hatches the current path: diagonal lines `spacing` screen pixels apart, clipped to it. The
 * lines are fixed to the screen, so neighbouring areas hatch seamlessly.
 */
export function hatchCurrentPath(ctx: CanvasRenderingContext2D, bounds: { minX: number; minY: number; maxX: number; maxY: number }, color: string, spacing = 8, width = 1.5): void {
  ctx.save();
  ctx.clip();
  ctx.strokeStyle = color;
  ctx.lineWidth = width;
  ctx.beginPath();
  const h = bounds.maxY - bounds.minY;
  // Lines x - y = c (45 degrees on screen), c on a lattice of `spacing` so they do not crawl on pan.
  const start = Math.floor((bounds.minX - bounds.maxY) / spacing) * spacing;
  for (let c = start; c <= bounds.maxX - bounds.minY; c += spacing) {
    ctx.moveTo(c + bounds.minY, bounds.minY);
    ctx.lineTo(c + bounds.minY + h, bounds.maxY);
  }
  ctx.stroke();
  ctx.restore();
}
