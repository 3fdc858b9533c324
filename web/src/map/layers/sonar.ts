// Sonar cones (the `sonar` topic): each reading as a translucent wedge out to its range, with an
// arc at the range when it is an echo (inside [range_min, range_max)) rather than "nothing seen".
// The IR ring (ir.ts) draws its readings, which have the same shape, with drawRangeCone.

import type { MapFrame, MapLayer, Redraw } from '../layer';

/** One range sensor's reading, its pose in the map frame (the `sonar` and `ir` topics). */
export interface SonarReading {
  x: number;
  y: number;
  theta: number;
  cone: number;
  range: number;
  range_min: number;
  range_max: number;
}

export interface ConeStyle {
  fill: string;
  echo: string;
}

const SONAR_STYLE: ConeStyle = { fill: 'rgba(56, 189, 248, 0.10)', echo: 'rgba(56, 189, 248, 0.55)' };
/** Narrowest cone drawn (rad), so a zero-width beam still shows. */
const MIN_CONE_RAD = 0.01;

export class SonarLayer implements MapLayer {
  readonly id = 'sonar';
  readonly toggle = 'sonar';
  private readings: SonarReading[] = [];

  constructor(private readonly redraw: Redraw) {}

  set(readings: SonarReading[]): void {
    this.readings = readings;
    this.redraw();
  }

  draw(frame: MapFrame): void {
    for (const reading of this.readings) drawRangeCone(frame, reading, SONAR_STYLE);
  }
}

/** A reading as a wedge out to its range (filled), with the echo arc when something echoed. */
export function drawRangeCone({ ctx, view }: MapFrame, r: SonarReading, style: ConeStyle): void {
  const echo = r.range >= r.range_min && r.range < r.range_max;
  const range = Math.min(Math.max(r.range, 0), r.range_max);
  if (!(range > 0)) return;
  const [sx, sy] = view.toScreen(r.x, r.y);
  const radius = range * view.scale;
  const half = Math.max(r.cone, MIN_CONE_RAD) / 2;
  // Screen y points down, so angles are negated.
  const from = -r.theta - half;
  const to = -r.theta + half;
  ctx.beginPath();
  ctx.moveTo(sx, sy);
  ctx.arc(sx, sy, radius, from, to);
  ctx.closePath();
  ctx.fillStyle = style.fill;
  ctx.fill();
  if (echo) {
    ctx.beginPath();
    ctx.arc(sx, sy, radius, from, to);
    ctx.strokeStyle = style.echo;
    ctx.lineWidth = 2;
    ctx.stroke();
  }
}
