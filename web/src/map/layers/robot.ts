// The robot at its estimated pose. A differential robot: the square footprint and a heading
// chevron. A tricycle (tricycle.ts): its footprint outline, the rear wheels on the rear axle (the
// base origin) and the front wheel wheelbase_m ahead, turned by the steering angle, so the map
// shows it steer.

import type { Pose2D } from '../../frames';
import { DIFFERENTIAL, sameBody, tricycleShape } from '../../tricycle';
import type { Point, RobotBody, TricycleGeometry, WheelShape } from '../../tricycle';
import type { MapFrame, MapLayer } from '../layer';
import type { ViewTransform } from '../view_transform';

/** Side of the square footprint (m). */
export const FOOTPRINT_M = 0.6;

const ESTIMATE_STYLE = { fill: 'rgba(56, 189, 248, 0.22)', stroke: '#38bdf8', heading: '#f8fafc' };
/** The simulator's true pose is drawn as a dashed outline in this colour (the truth layer). */
export const GHOST_COLOR = '#c4b5fd';
const WHEEL_FILL = '#0f172a';
const WHEEL_STROKE = '#e2e8f0';
/** The steered wheel stands out from the rear ones. */
const FRONT_WHEEL_STROKE = '#fbbf24';

export class RobotLayer implements MapLayer {
  readonly id = 'robot';
  readonly showsRobot = true;
  /** What the robot looks like (from /robot: kinematics and geometry). */
  body: RobotBody = DIFFERENTIAL;
  /** The front wheel's angle (rad, CCW) of the latest pose; 0 until one says. */
  steering = 0;

  /** True when the drawing changed. */
  setBody(body: RobotBody): boolean {
    if (sameBody(body, this.body)) return false;
    this.body = body;
    return true;
  }

  draw({ ctx, view, scene }: MapFrame): void {
    if (!scene.pose) return;
    if (this.body.kind === 'tricycle') drawTricycle(ctx, view, scene.pose, this.body.geometry, this.steering, false);
    else drawFootprint(ctx, view, scene.pose, false);
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
  tracePoints(ctx, corners);
  strokeBody(ctx, ghost);
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

/**
 * A tricycle at `pose` (the rear-axle centre): the outline, the chassis from the rear axle to the
 * front wheel, the wheels. The ghost (true pose, which has no steering) is the outline alone.
 */
export function drawTricycle(
  ctx: CanvasRenderingContext2D,
  view: ViewTransform,
  pose: Pose2D,
  geometry: TricycleGeometry,
  steering: number,
  ghost: boolean,
): void {
  const shape = tricycleShape(pose, geometry, steering);
  const screen = (p: Point): Point => view.toScreen(p[0], p[1]);
  tracePoints(ctx, shape.outline.map(screen));
  strokeBody(ctx, ghost);
  if (ghost) return;
  // The chassis: rear axle (between the rear wheels) to the front wheel.
  const [left, right] = shape.rearWheels;
  ctx.beginPath();
  ctx.moveTo(...screen(left.center));
  ctx.lineTo(...screen(right.center));
  ctx.moveTo(...screen(shape.rearAxle));
  ctx.lineTo(...screen(shape.frontAxle));
  ctx.strokeStyle = ESTIMATE_STYLE.heading;
  ctx.lineWidth = 1.5;
  ctx.stroke();
  drawWheel(ctx, view, left, WHEEL_STROKE);
  drawWheel(ctx, view, right, WHEEL_STROKE);
  drawWheel(ctx, view, shape.frontWheel, FRONT_WHEEL_STROKE);
  // Where the front wheel rolls: a short line ahead of it along its direction.
  const reach = shape.wheelLength * 1.2;
  const { center, angle } = shape.frontWheel;
  ctx.beginPath();
  ctx.moveTo(...screen(center));
  ctx.lineTo(...screen([center[0] + reach * Math.cos(angle), center[1] + reach * Math.sin(angle)]));
  ctx.strokeStyle = FRONT_WHEEL_STROKE;
  ctx.lineWidth = 2;
  ctx.stroke();
}

function drawWheel(ctx: CanvasRenderingContext2D, view: ViewTransform, wheel: WheelShape, stroke: string): void {
  tracePoints(ctx, wheel.corners.map(([x, y]) => view.toScreen(x, y)));
  ctx.fillStyle = WHEEL_FILL;
  ctx.fill();
  ctx.strokeStyle = stroke;
  ctx.lineWidth = 1.5;
  ctx.stroke();
}

function tracePoints(ctx: CanvasRenderingContext2D, points: readonly Point[]): void {
  ctx.beginPath();
  points.forEach(([x, y], i) => (i === 0 ? ctx.moveTo(x, y) : ctx.lineTo(x, y)));
  ctx.closePath();
}

function strokeBody(ctx: CanvasRenderingContext2D, ghost: boolean): void {
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
}
