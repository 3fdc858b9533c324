// Navigation goals on the dashboard: the goal JSON of mobotd, a small store that merges the REST
// list with the `goal` / `path` topics, and the pure geometry the map draws (covariance ellipse,
// heading uncertainty, press-and-drag headings). No DOM here, so all of it is unit-tested.

export type GoalStatus = 'planning' | 'active' | 'succeeded' | 'failed' | 'canceled';

export interface GoalTarget {
  x: number;
  y: number;
  theta?: number;
}

/** A goal as mobotd reports it (GET /api/v1/goals, the `goal` topic, POST replies). */
export interface Goal {
  id: number;
  status: GoalStatus;
  reason?: string;
  target: GoalTarget;
  planner?: string;
  controller?: string;
  path?: [number, number][];
  replans?: number;
  created_t?: number;
  ended_t?: number;
}

/** The `path` topic: the plan of one goal (re-sent on every replan). */
export interface PathMessage {
  goal_id: number;
  points: [number, number][];
}

export const FINISHED: ReadonlySet<string> = new Set(['succeeded', 'failed', 'canceled']);

export function isFinished(goal: Pick<Goal, 'status'> | null | undefined): boolean {
  return !!goal && FINISHED.has(goal.status);
}

/** Planners of the contract; `available` are the ones this server build runs (controllers: controllers.ts). */
export const PLANNERS = [
  { name: 'astar', label: 'A* (grid)', available: true },
  { name: 'voronoi', label: 'Voronoi roadmap', available: true },
] as const;

/** Validates a goal-shaped value from the wire; null when it is not one. */
export function parseGoal(value: unknown): Goal | null {
  if (!value || typeof value !== 'object') return null;
  const g = value as Record<string, unknown>;
  const target = g.target as Record<string, unknown> | undefined;
  if (typeof g.id !== 'number' || typeof g.status !== 'string' || !target) return null;
  if (typeof target.x !== 'number' || typeof target.y !== 'number') return null;
  const goal: Goal = {
    id: g.id,
    status: g.status as GoalStatus,
    target: { x: target.x, y: target.y },
  };
  if (typeof target.theta === 'number') goal.target.theta = target.theta;
  if (typeof g.reason === 'string') goal.reason = g.reason;
  if (typeof g.planner === 'string') goal.planner = g.planner;
  if (typeof g.controller === 'string') goal.controller = g.controller;
  if (Array.isArray(g.path)) goal.path = parsePoints(g.path);
  if (typeof g.replans === 'number') goal.replans = g.replans;
  if (typeof g.created_t === 'number') goal.created_t = g.created_t;
  if (typeof g.ended_t === 'number') goal.ended_t = g.ended_t;
  return goal;
}

export function parsePoints(value: unknown): [number, number][] {
  if (!Array.isArray(value)) return [];
  const out: [number, number][] = [];
  for (const p of value) {
    if (Array.isArray(p) && typeof p[0] === 'number' && typeof p[1] === 'number' && Number.isFinite(p[0]) && Number.isFinite(p[1])) {
      out.push([p[0], p[1]]);
    }
  }
  return out;
}

/**
 * Goals by id plus the current goal (the newest one) and its path. Goal frames may carry an
 * empty path (planning, ended goals); the last non-empty plan of the current goal is kept so the
 * map can still show where the robot was sent.
 */
export class GoalStore {
  private readonly goals = new Map<number, Goal>();
  private pathGoalId: number | null = null;
  path: [number, number][] = [];
  /** Bumped on every change; the UI redraws when it moved. */
  version = 0;

  constructor(private readonly keep = 20) {}

  /** Replaces everything with a REST listing (on connect). */
  reset(goals: Goal[]): void {
    this.goals.clear();
    this.path = [];
    this.pathGoalId = null;
    for (const goal of goals) this.upsert(goal);
    this.version++;
  }

  upsert(goal: Goal): void {
    const previous = this.goals.get(goal.id);
    const merged: Goal = { ...previous, ...goal, target: { ...goal.target } };
    // A frame without a path does not erase the plan we already know.
    if ((!goal.path || goal.path.length === 0) && previous?.path?.length) merged.path = previous.path;
    this.goals.set(goal.id, merged);
    this.trim();
    this.syncPath();
    this.version++;
  }

  /** A `path` frame: the plan (or replan) of a goal. */
  setPath(message: PathMessage): void {
    const goal = this.goals.get(message.goal_id);
    if (goal) goal.path = message.points;
    const current = this.current;
    if (!current || message.goal_id >= current.id) {
      this.path = message.points;
      this.pathGoalId = message.goal_id;
    }
    this.version++;
  }

  /** The goal whose plan `path` is (null: none). */
  get pathGoal(): number | null {
    return this.pathGoalId;
  }

  private syncPath(): void {
    const current = this.current;
    if (!current) {
      this.path = [];
      this.pathGoalId = null;
      return;
    }
    // A path frame of a goal we have not heard of yet is newer than everything: keep it.
    if (this.pathGoalId !== null && this.pathGoalId > current.id) return;
    if (current.path && current.path.length > 0) {
      this.path = current.path;
      this.pathGoalId = current.id;
    } else if (this.pathGoalId !== current.id) {
      this.path = [];
      this.pathGoalId = current.id;
    }
  }

  /** The newest goal, or null. */
  get current(): Goal | null {
    let best: Goal | null = null;
    for (const goal of this.goals.values()) if (!best || goal.id > best.id) best = goal;
    return best;
  }

  get(id: number): Goal | undefined {
    return this.goals.get(id);
  }

  /** Newest first. */
  recent(limit = 8): Goal[] {
    return [...this.goals.values()].sort((a, b) => b.id - a.id).slice(0, limit);
  }

  get size(): number {
    return this.goals.size;
  }

  private trim(): void {
    if (this.goals.size <= this.keep) return;
    const ids = [...this.goals.keys()].sort((a, b) => a - b);
    for (const id of ids.slice(0, ids.length - this.keep)) this.goals.delete(id);
  }
}

/** Seconds the goal has run: to its end, or to `now` (robot clock) while it runs. */
export function goalElapsed(goal: Goal, now: number | null): number | null {
  if (goal.created_t === undefined) return null;
  const end = goal.ended_t ?? (isFinished(goal) ? undefined : now ?? undefined);
  if (end === undefined) return null;
  return Math.max(0, end - goal.created_t);
}

/** Straight-line distance from a pose to the goal's target. */
export function distanceToTarget(goal: Goal, pose: { x: number; y: number } | null): number | null {
  if (!pose) return null;
  return Math.hypot(goal.target.x - pose.x, goal.target.y - pose.y);
}

/** Length of a polyline. */
export function pathLength(points: readonly (readonly [number, number])[]): number {
  let length = 0;
  for (let i = 1; i < points.length; i++) {
    length += Math.hypot(points[i]![0] - points[i - 1]![0], points[i]![1] - points[i - 1]![1]);
  }
  return length;
}

// ---- uncertainty ----

export interface Ellipse {
  /** Semi-axes (m), major >= minor. */
  major: number;
  minor: number;
  /** Angle of the major axis from +x (rad, map frame). */
  angle: number;
}

/**
 * The `sigmas`-sigma ellipse of the x-y block of a row-major 3x3 covariance (eigen decomposition
 * of the symmetric 2x2 block). Null when the covariance is missing or not a valid one.
 */
export function covarianceEllipse(cov: readonly number[] | undefined | null, sigmas = 2): Ellipse | null {
  if (!cov || cov.length < 5) return null;
  const a = cov[0]!;
  const b = (cov[1]! + cov[3]!) / 2;
  const c = cov[4]!;
  if (![a, b, c].every(Number.isFinite) || a < 0 || c < 0) return null;
  const mean = (a + c) / 2;
  const radius = Math.hypot((a - c) / 2, b);
  const l1 = mean + radius;
  const l2 = Math.max(0, mean - radius);
  // Major-axis direction: the eigenvector of l1.
  const angle = radius < 1e-15 ? 0 : 0.5 * Math.atan2(2 * b, a - c);
  return { major: sigmas * Math.sqrt(l1), minor: sigmas * Math.sqrt(l2), angle };
}

/** Standard deviation of the heading (rad) from a row-major 3x3 covariance, or null. */
export function headingSigma(cov: readonly number[] | undefined | null): number | null {
  if (!cov || cov.length < 9) return null;
  const v = cov[8]!;
  return Number.isFinite(v) && v >= 0 ? Math.sqrt(v) : null;
}

// ---- press and drag on the map ----

/** Below this drag (screen pixels) a press is a plain click: no heading. */
export const DRAG_THRESHOLD_PX = 8;

/**
 * The heading of a press-and-drag on the map, or null for a plain click. Points are in the map
 * frame; `scale` is pixels per metre so the threshold is in screen pixels.
 */
export function dragHeading(
  press: { x: number; y: number },
  release: { x: number; y: number },
  scale: number,
  thresholdPx = DRAG_THRESHOLD_PX,
): number | null {
  const dx = release.x - press.x;
  const dy = release.y - press.y;
  if (Math.hypot(dx, dy) * scale < thresholdPx) return null;
  return Math.atan2(dy, dx);
}

/** Angle wrapped to (-pi, pi]. */
export function wrapAngle(a: number): number {
  let r = a % (2 * Math.PI);
  if (r <= -Math.PI) r += 2 * Math.PI;
  if (r > Math.PI) r -= 2 * Math.PI;
  return r;
}
