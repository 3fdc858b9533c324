import { describe, expect, it } from 'vitest';
import {
  covarianceEllipse,
  distanceToTarget,
  dragHeading,
  goalElapsed,
  GoalStore,
  headingSigma,
  parseGoal,
  pathLength,
  wrapAngle,
} from '../src/goals';
import type { Goal } from '../src/goals';

const goal = (id: number, status: Goal['status'], extra: Partial<Goal> = {}): Goal => ({
  id,
  status,
  target: { x: id, y: 7.5 },
  ...extra,
});

describe('covarianceEllipse', () => {
  it('gives axis-aligned 2-sigma radii for a diagonal covariance', () => {
    const e = covarianceEllipse([0.04, 0, 0, 0, 0.01, 0, 0, 0, 0.001])!;
    expect(e.major).toBeCloseTo(0.4); // 2 * sqrt(0.04)
    expect(e.minor).toBeCloseTo(0.2);
    expect(e.angle).toBeCloseTo(0);
  });

  it('puts the major axis along y when y is the uncertain direction', () => {
    const e = covarianceEllipse([0.01, 0, 0, 0, 0.09, 0, 0, 0, 0], 1)!;
    expect(e.major).toBeCloseTo(0.3);
    expect(e.minor).toBeCloseTo(0.1);
    expect(Math.abs(e.angle)).toBeCloseTo(Math.PI / 2);
  });

  it('turns a correlated covariance by 45 degrees', () => {
    // [[2, 1], [1, 2]]: eigenvalues 3 and 1, major axis along (1, 1).
    const e = covarianceEllipse([2, 1, 0, 1, 2, 0, 0, 0, 0], 1)!;
    expect(e.major).toBeCloseTo(Math.sqrt(3));
    expect(e.minor).toBeCloseTo(1);
    expect(e.angle).toBeCloseTo(Math.PI / 4);
    // The major axis is an eigenvector: Sigma v = lambda v.
    const v = [Math.cos(e.angle), Math.sin(e.angle)];
    expect(2 * v[0]! + 1 * v[1]!).toBeCloseTo(3 * v[0]!);
  });

  it('handles circles, a singular block and bad input', () => {
    const circle = covarianceEllipse([0.25, 0, 0, 0, 0.25, 0, 0, 0, 0], 2)!;
    expect(circle.major).toBeCloseTo(1);
    expect(circle.minor).toBeCloseTo(1);
    const line = covarianceEllipse([1, 1, 0, 1, 1, 0, 0, 0, 0], 1)!;
    expect(line.minor).toBeCloseTo(0);
    expect(line.major).toBeCloseTo(Math.SQRT2);
    expect(covarianceEllipse(undefined)).toBeNull();
    expect(covarianceEllipse([NaN, 0, 0, 0, 1, 0, 0, 0, 0])).toBeNull();
    expect(covarianceEllipse([-1, 0, 0, 0, 1, 0, 0, 0, 0])).toBeNull();
  });
});

describe('headingSigma', () => {
  it('is the square root of the theta variance', () => {
    expect(headingSigma([0, 0, 0, 0, 0, 0, 0, 0, 0.0004])).toBeCloseTo(0.02);
    expect(headingSigma([1, 0, 0])).toBeNull();
    expect(headingSigma([0, 0, 0, 0, 0, 0, 0, 0, -1])).toBeNull();
  });
});

describe('dragHeading', () => {
  it('is null for a plain click and the drag direction otherwise', () => {
    // 40 px per metre: 0.1 m is 4 px, below the 8 px threshold.
    expect(dragHeading({ x: 1, y: 1 }, { x: 1.1, y: 1 }, 40)).toBeNull();
    expect(dragHeading({ x: 1, y: 1 }, { x: 2, y: 1 }, 40)).toBeCloseTo(0);
    expect(dragHeading({ x: 1, y: 1 }, { x: 1, y: 2 }, 40)).toBeCloseTo(Math.PI / 2);
    expect(dragHeading({ x: 1, y: 1 }, { x: 0, y: 1 }, 40)).toBeCloseTo(Math.PI);
    expect(dragHeading({ x: 0, y: 0 }, { x: 0, y: -1 }, 40)).toBeCloseTo(-Math.PI / 2);
  });

  it('wraps angles', () => {
    expect(wrapAngle(3 * Math.PI)).toBeCloseTo(Math.PI);
    expect(wrapAngle(-Math.PI / 2 - 4 * Math.PI)).toBeCloseTo(-Math.PI / 2);
  });
});

describe('parseGoal', () => {
  it('reads the goal JSON of mobotd and rejects other shapes', () => {
    const g = parseGoal({
      id: 3,
      status: 'active',
      target: { x: 5, y: 7.5, theta: 1.5 },
      planner: 'astar',
      controller: 'lyapunov',
      path: [[2, 7.5], [3, 7.5], ['bad'], [5, 7.5]],
      replans: 1,
      created_t: 10,
    })!;
    expect(g.target.theta).toBe(1.5);
    expect(g.path).toEqual([[2, 7.5], [3, 7.5], [5, 7.5]]);
    expect(g.replans).toBe(1);
    expect(parseGoal({ id: 1, status: 'active' })).toBeNull();
    expect(parseGoal(null)).toBeNull();
    const noHeading = parseGoal({ id: 4, status: 'planning', target: { x: 1, y: 2 } })!;
    expect(noHeading.target.theta).toBeUndefined();
  });
});

describe('GoalStore', () => {
  it('tracks the newest goal and its path across goal and path frames', () => {
    const store = new GoalStore();
    store.upsert(goal(1, 'active', { path: [[0, 0], [1, 0]] }));
    expect(store.current?.id).toBe(1);
    expect(store.path).toHaveLength(2);
    // A replan arrives on the path topic.
    store.setPath({ goal_id: 1, points: [[0, 0], [0.5, 0.5], [1, 0]] });
    expect(store.path).toHaveLength(3);
    // The final status frame may come without a path: the plan stays.
    store.upsert(goal(1, 'succeeded', { path: [] }));
    expect(store.current?.status).toBe('succeeded');
    expect(store.path).toHaveLength(3);
    // A new goal replaces the path; a late path of the old goal does not.
    store.upsert(goal(2, 'active', { path: [[1, 0], [2, 0]] }));
    store.setPath({ goal_id: 1, points: [[9, 9], [8, 8]] });
    expect(store.current?.id).toBe(2);
    expect(store.path).toEqual([[1, 0], [2, 0]]);
    // A new goal without a path yet clears the old one.
    store.upsert(goal(3, 'planning'));
    expect(store.path).toEqual([]);
  });

  it('lists recent goals newest first, keeps a bounded history and resets from REST', () => {
    const store = new GoalStore(3);
    for (let id = 1; id <= 5; id++) store.upsert(goal(id, 'succeeded'));
    expect(store.size).toBe(3);
    expect(store.recent().map((g) => g.id)).toEqual([5, 4, 3]);
    store.reset([goal(7, 'failed', { reason: 'no_path' }), goal(6, 'canceled')]);
    expect(store.size).toBe(2);
    expect(store.current?.id).toBe(7);
    const before = store.version;
    store.upsert(goal(7, 'failed'));
    expect(store.version).toBeGreaterThan(before);
  });
});

describe('goal figures', () => {
  it('elapsed runs on the robot clock until the goal ends', () => {
    expect(goalElapsed(goal(1, 'active', { created_t: 10 }), 14.5)).toBeCloseTo(4.5);
    expect(goalElapsed(goal(1, 'succeeded', { created_t: 10, ended_t: 12 }), 99)).toBeCloseTo(2);
    expect(goalElapsed(goal(1, 'active'), 14)).toBeNull();
    expect(goalElapsed(goal(1, 'active', { created_t: 10 }), null)).toBeNull();
  });

  it('distance remaining is from the pose to the target; path length sums segments', () => {
    expect(distanceToTarget(goal(5, 'active'), { x: 2, y: 3.5 })).toBeCloseTo(5);
    expect(distanceToTarget(goal(5, 'active'), null)).toBeNull();
    expect(pathLength([[0, 0], [3, 4], [3, 5]])).toBeCloseTo(6);
    expect(pathLength([])).toBe(0);
  });
});
