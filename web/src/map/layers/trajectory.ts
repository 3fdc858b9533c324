// A recorded trajectory over the map (the Runs page): the line, a hollow dot at the start and a
// filled one at the end.

import { BACKGROUND } from '../colors';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { packPoints, strokePolyline } from '../shapes';

const TRAJECTORY_COLOR = '#34d399';
const END_DOT_RADIUS_PX = 5;

export class TrajectoryLayer implements MapLayer {
  readonly id = 'trajectory';
  private xy: Float64Array | null = null;

  constructor(private readonly redraw: Redraw) {}

  /** The trajectory to draw, or null for none. */
  set(points: readonly { x: number; y: number }[] | null): void {
    this.xy = points ? packPoints(points, (p) => p.x, (p) => p.y) : null;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    const xy = this.xy;
    const n = xy ? xy.length / 2 : 0;
    if (!xy || n === 0) return;
    strokePolyline(ctx, view, xy, { color: TRAJECTORY_COLOR, width: 2 });
    const [sx, sy] = view.toScreen(xy[0]!, xy[1]!);
    const [ex, ey] = view.toScreen(xy[2 * n - 2]!, xy[2 * n - 1]!);
    ctx.lineWidth = 2;
    ctx.strokeStyle = TRAJECTORY_COLOR;
    ctx.fillStyle = BACKGROUND;
    ctx.beginPath();
    ctx.arc(sx, sy, END_DOT_RADIUS_PX, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = TRAJECTORY_COLOR;
    ctx.beginPath();
    ctx.arc(ex, ey, END_DOT_RADIUS_PX, 0, 2 * Math.PI);
    ctx.fill();
  }
}
