// The robot at its estimated pose: the square footprint and a heading chevron.

import type { Pose2D } from '../../frames';
import type { MapFrame, MapLayer } from '../layer';
import type { ViewTransform } from '../view_transform';

/** Side of the square footprint (m). */
export const FOOTPRINT_M = 0.6;

const ESTIMATE_STYLE = { fill: 'rgba(56, 189, 248, 0.22)', stroke: '#38bdf8', heading: '#f8fafc' };
/** The simulator's true pose is drawn as a dashed outline in this colour (the truth layer). */
export const GHOST_COLOR = '#c4b5fd';

export class RobotLayer implements MapLayer {
  readonly id = 'robot';
  readonly showsRobot = true;

  draw({ ctx, view, scene }: MapFrame): void {
    if (scene.pose) drawFootprint(ctx, view, scene.pose, false);
  }
}

/** The footprint at `pose`: filled for the estimate, dashed outline for the ghost (true pose). */
export function drawFootprint(ctx: CanvasRenderingContext2D, view: ViewTransform, pose: Pose2D, ghost: boolean): void {
  const half = FOOTPRINT_M / 2;
  const c = Math.cos(pose.theta);
  const s = Math.sin(pose.theta);
  /** Robot-frame point (forward lx, left ly) on screen. */
  const corner = (lx: number, ly: number): [number, number] => view.toScreen(pose.x + c * lx - s * ly, pose.y + s * lx + c * ly);
  const corners = [corner(half, half), corner(-half, half), corner(-half, -half), corner(half, -half)];
  ctx.beginPath();
  corners.forEach(([x, y], i) => (i === 0 ? ctx.moveTo(x, y) : ctx.lineTo(x, y)));
  ctx.closePath();
  if (ghost) {
    ctx.setLineDash([5, 4]);
    ctx.strokeStyle = GHOST_COLOR;
    ctx.lineWidth = 1.5;
    ctx.stroke();
    ctx.setLineDash([]);
  } else {
    ctx.fillStyle = ESTIMATE_STYLE.fill;
    ctx.fill();
    ctx.strokeStyle = ESTIMATE_STYLE.stroke;
    ctx.lineWidth = 2;
    ctx.stroke();
  }
  // Heading: a line from the centre to past the front edge and an arrow head.
  const [cx, cy] = view.toScreen(pose.x, pose.y);
  const [fx, fy] = corner(half * 1.5, 0);
  const [l, r] = [corner(half * 1.05, half * 0.35), corner(half * 1.05, -half * 0.35)];
  ctx.beginPath();
  ctx.moveTo(cx, cy);
  ctx.lineTo(fx, fy);
  ctx.moveTo(l[0], l[1]);
  ctx.lineTo(fx, fy);
  ctx.lineTo(r[0], r[1]);
  ctx.strokeStyle = ghost ? GHOST_COLOR : ESTIMATE_STYLE.heading;
  ctx.lineWidth = ghost ? 1.5 : 2;
  ctx.stroke();
}
