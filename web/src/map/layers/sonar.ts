// Sonar cones (the `sonar` topic): each reading as a translucent wedge out to its range, with an
// arc at the range when it is an echo (inside [range_min, range_max)) rather than "nothing seen".

import type { MapFrame, MapLayer, Redraw } from '../layer';

export interface SonarReading {
  x: number;
  y: number;
  theta: number;
  cone: number;
  range: number;
  range_min: number;
  range_max: number;
}

const CONE_FILL = 'rgba(56, 189, 248, 0.10)';
const ECHO_STROKE = 'rgba(56, 189, 248, 0.55)';
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
    for (const reading of this.readings) drawCone(frame, reading);
  }
}

function drawCone({ ctx, view }: MapFrame, r: SonarReading): void {
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
  ctx.fillStyle = CONE_FILL;
  ctx.fill();
  if (echo) {
    ctx.beginPath();
    ctx.arc(sx, sy, radius, from, to);
    ctx.strokeStyle = ECHO_STROKE;
    ctx.lineWidth = 2;
    ctx.stroke();
  }
}
