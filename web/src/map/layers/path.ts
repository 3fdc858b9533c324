// The planned path of the current goal (the `path` topic): a cased line with dots at the
// waypoints while the goal runs, a faded dashed line once it has ended.

import type { MapFrame, MapLayer, Redraw } from '../layer';
import { packPoints, strokePolyline } from '../shapes';

export const PATH_COLOR = '#34d399';
const DONE_COLOR = 'rgba(52, 211, 153, 0.35)';
/** A dark casing under the line keeps it readable over the map and the scan. */
const CASING = { color: 'rgba(11, 15, 20, 0.75)', width: 5 };
const WAYPOINT_RADIUS_PX = 2.2;

export class PathLayer implements MapLayer {
  readonly id = 'path';
  readonly toggle = 'path';
  private xy: Float64Array = new Float64Array(0);
  /** The goal has ended: the path is drawn faded. */
  private done = false;

  constructor(private readonly redraw: Redraw) {}

  /** The current plan as [x, y] pairs; `done` when its goal has ended. */
  set(points: readonly (readonly [number, number])[], done = false): void {
    this.xy = packPoints(points, (p) => p[0], (p) => p[1]);
    this.done = done;
    this.redraw();
  }

  get points(): number {
    return this.xy.length / 2;
  }

  draw({ ctx, view }: MapFrame): void {
    if (this.points < 2) return;
    if (this.done) {
      ctx.setLineDash([6, 5]);
      strokePolyline(ctx, view, this.xy, { color: DONE_COLOR, width: 2 });
      ctx.setLineDash([]);
      return;
    }
    strokePolyline(ctx, view, this.xy, CASING);
    strokePolyline(ctx, view, this.xy, { color: PATH_COLOR, width: 2.5 });
    this.drawWaypoints(ctx, view);
  }

  /** Dots at the inner waypoints (the ends are the robot and the goal marker). */
  private drawWaypoints(ctx: CanvasRenderingContext2D, view: MapFrame['view']): void {
    const r = WAYPOINT_RADIUS_PX;
    ctx.fillStyle = PATH_COLOR;
    ctx.beginPath();
    for (let i = 1; i < this.points - 1; i++) {
      const sx = view.toScreenX(this.xy[2 * i]!);
      const sy = view.toScreenY(this.xy[2 * i + 1]!);
      ctx.moveTo(sx + r, sy);
      ctx.arc(sx, sy, r, 0, 2 * Math.PI);
    }
    ctx.fill();
  }
}
