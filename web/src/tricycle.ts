// The robot's body as the map draws it. A differential robot keeps the square footprint of
// map/layers/robot.ts; a tricycle (`kinematics` tricycle_t1 / tricycle_t2 in /robot and the
// status topic) is drawn from its `geometry`: the footprint outline (its centre
// footprint_offset_m ahead of the base origin, which is the rear-axle centre), the two rear
// wheels on the rear axle and the steered front wheel wheelbase_m ahead, turned by the pose's
// `steering_rad`. Pure (no DOM): unit-tested.

import type { Pose2D } from './frames';
import { deg } from './ui';

export type TricycleKinematics = 'tricycle_t1' | 'tricycle_t2';

/** /robot `geometry` in metres, as the contract names it. */
export interface JsonGeometry {
  wheelbase_m?: number;
  footprint_length_m?: number;
  footprint_width_m?: number;
  footprint_offset_m?: number;
}

export interface TricycleGeometry {
  /** Rear axle to front wheel (m). */
  wheelbase: number;
  /** Footprint along the robot (m). */
  length: number;
  /** Footprint across the robot (m). */
  width: number;
  /** How far the footprint's centre is ahead of the rear axle (m). */
  offset: number;
}

export type RobotBody =
  | { kind: 'differential' }
  | {
      kind: 'tricycle';
      kinematics: TricycleKinematics;
      geometry: TricycleGeometry;
      /** The status carried no (valid) geometry: DEFAULT_TRICYCLE is drawn. */
      assumed: boolean;
    };

/** Drawn when a tricycle's status has no geometry: a 0.6 m square body with a 0.4 m wheelbase. */
export const DEFAULT_TRICYCLE: TricycleGeometry = { wheelbase: 0.4, length: 0.6, width: 0.6, offset: 0.2 };

export const DIFFERENTIAL: RobotBody = { kind: 'differential' };

export function isTricycle(kinematics: unknown): kinematics is TricycleKinematics {
  return kinematics === 'tricycle_t1' || kinematics === 'tricycle_t2';
}

const positive = (x: unknown): x is number => typeof x === 'number' && Number.isFinite(x) && x > 0;

/** The geometry of a /robot body, or null when a field is missing or not a positive (offset: finite) number. */
export function parseGeometry(value: unknown): TricycleGeometry | null {
  if (!value || typeof value !== 'object') return null;
  const g = value as JsonGeometry;
  const offset = g.footprint_offset_m ?? 0;
  if (!positive(g.wheelbase_m) || !positive(g.footprint_length_m) || !positive(g.footprint_width_m)) return null;
  if (typeof offset !== 'number' || !Number.isFinite(offset)) return null;
  return { wheelbase: g.wheelbase_m, length: g.footprint_length_m, width: g.footprint_width_m, offset };
}

/** The body to draw for a /robot (or status topic) body; anything but a tricycle is differential. */
export function robotBody(status: { kinematics?: unknown; geometry?: unknown } | null | undefined): RobotBody {
  if (!status || !isTricycle(status.kinematics)) return DIFFERENTIAL;
  const geometry = parseGeometry(status.geometry);
  return { kind: 'tricycle', kinematics: status.kinematics, geometry: geometry ?? DEFAULT_TRICYCLE, assumed: geometry === null };
}

/** Whether two bodies draw the same. */
export function sameBody(a: RobotBody, b: RobotBody): boolean {
  if (a.kind !== b.kind) return false;
  if (a.kind === 'differential' || b.kind === 'differential') return true;
  const [g, h] = [a.geometry, b.geometry];
  return a.kinematics === b.kinematics && g.wheelbase === h.wheelbase && g.length === h.length && g.width === h.width && g.offset === h.offset;
}

export type Point = [number, number];

/** A wheel seen from above: a rectangle centred at `center`, its long side along `angle` (map frame). */
export interface WheelShape {
  center: Point;
  angle: number;
  /** Map-frame corners: front-left, rear-left, rear-right, front-right (of the wheel). */
  corners: Point[];
}

export interface TricycleShape {
  /** Map-frame corners of the footprint: front-left, rear-left, rear-right, front-right. */
  outline: Point[];
  /** The base origin (rear-axle centre) and the front wheel's contact point. */
  rearAxle: Point;
  frontAxle: Point;
  /** Left, then right. */
  rearWheels: [WheelShape, WheelShape];
  frontWheel: WheelShape;
  /** Wheel size (m): diameter (long side) and tread (short side). */
  wheelLength: number;
  wheelWidth: number;
}

/** Wheel diameter from the wheelbase: a third of it, within 0.08..0.35 m. */
export function wheelSize(geometry: TricycleGeometry): { length: number; width: number } {
  const length = Math.min(0.35, Math.max(0.08, geometry.wheelbase / 3));
  return { length, width: length * 0.4 };
}

/** Robot-frame point (forward lx, left ly) -> map frame at `pose`. */
export function toMap(pose: Pose2D, lx: number, ly: number): Point {
  const c = Math.cos(pose.theta);
  const s = Math.sin(pose.theta);
  return [pose.x + c * lx - s * ly, pose.y + s * lx + c * ly];
}

function wheel(center: Point, angle: number, length: number, width: number): WheelShape {
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  const at = (lx: number, ly: number): Point => [center[0] + c * lx - s * ly, center[1] + s * lx + c * ly];
  const [l, w] = [length / 2, width / 2];
  return { center, angle, corners: [at(l, w), at(-l, w), at(-l, -w), at(l, -w)] };
}

/**
 * The tricycle at `pose` (the base origin: the rear-axle centre) with the front wheel turned by
 * `steering` (rad, counter-clockwise: positive steers left). Rear wheels sit on the rear axle just
 * inside the outline's sides.
 */
export function tricycleShape(pose: Pose2D, geometry: TricycleGeometry, steering: number): TricycleShape {
  const { wheelbase, length, width, offset } = geometry;
  const halfL = length / 2;
  const halfW = width / 2;
  const outline = [
    toMap(pose, offset + halfL, halfW),
    toMap(pose, offset - halfL, halfW),
    toMap(pose, offset - halfL, -halfW),
    toMap(pose, offset + halfL, -halfW),
  ];
  const size = wheelSize(geometry);
  // On the outline's side when the body is narrow, never across the centre line.
  const track = Math.max(size.width / 2, halfW - size.width / 2);
  const steer = Number.isFinite(steering) ? steering : 0;
  const frontAxle = toMap(pose, wheelbase, 0);
  return {
    outline,
    rearAxle: [pose.x, pose.y],
    frontAxle,
    rearWheels: [
      wheel(toMap(pose, 0, track), pose.theta, size.length, size.width),
      wheel(toMap(pose, 0, -track), pose.theta, size.length, size.width),
    ],
    frontWheel: wheel(frontAxle, pose.theta + steer, size.length, size.width),
    wheelLength: size.length,
    wheelWidth: size.width,
  };
}

/** The steering angle for the status panel: "12.3° left", "4.0° right", "0.0°"; "–" when unknown. */
export function steeringText(steering: number | null | undefined): string {
  if (steering === null || steering === undefined || !Number.isFinite(steering)) return '–';
  const magnitude = deg(Math.abs(steering));
  // Below 0.05 degrees it reads 0.0 either way.
  if (Math.abs(steering) < (0.05 * Math.PI) / 180) return magnitude;
  return `${magnitude} ${steering > 0 ? 'left' : 'right'}`;
}

/** "tricycle T1" / "tricycle T2" / "differential". */
export function kinematicsLabel(body: RobotBody): string {
  if (body.kind === 'differential') return 'differential';
  return body.kinematics === 'tricycle_t1' ? 'tricycle T1' : 'tricycle T2';
}
