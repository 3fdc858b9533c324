import { describe, expect, it } from 'vitest';
import { isSimplePolygon, polygonArea, polygonProblem, segmentsIntersect, signedArea } from '../src/polygon';
import type { Point } from '../src/polygon';

const square: Point[] = [[0, 0], [2, 0], [2, 2], [0, 2]];

describe('polygon geometry', () => {
  it('finds crossing, touching and collinear overlapping segments', () => {
    expect(segmentsIntersect([0, 0], [2, 2], [0, 2], [2, 0])).toBe(true);
    expect(segmentsIntersect([0, 0], [2, 0], [1, 0], [1, 3])).toBe(true); // touches
    expect(segmentsIntersect([0, 0], [2, 0], [1, 0], [3, 0])).toBe(true); // overlaps
    expect(segmentsIntersect([0, 0], [1, 0], [2, 0], [3, 0])).toBe(false); // collinear apart
    expect(segmentsIntersect([0, 0], [1, 1], [0, 1], [0.4, 0.6])).toBe(false);
  });

  it('measures area (counter-clockwise positive)', () => {
    expect(signedArea(square)).toBe(4);
    expect(signedArea([...square].reverse())).toBe(-4);
    expect(polygonArea([[0, 0], [4, 0], [0, 3]])).toBe(6);
  });

  it('takes simple polygons, convex or not', () => {
    expect(isSimplePolygon(square)).toBe(true);
    expect(isSimplePolygon([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]])).toBe(true);
    expect(isSimplePolygon([[0, 0], [1, 0], [0, 1]])).toBe(true);
  });

  it('says why a polygon is not simple', () => {
    expect(polygonProblem([[0, 0], [2, 2], [2, 0], [0, 2]])).toBe('edges cross'); // bow tie
    expect(polygonProblem([[0, 0], [1, 0]])).toMatch(/at least 3/);
    expect(polygonProblem([[0, 0], [1, 0], [1, 0], [0, 1]])).toMatch(/coincide/);
    expect(polygonProblem([[0, 0], [2, 0], [1, 0], [1, 1]])).toMatch(/folds back/);
    expect(polygonProblem([[0, 0], [1, 0], [2, 0]])).toMatch(/folds back|no area/);
    expect(polygonProblem(Array.from({ length: 257 }, (_, i) => [Math.cos(i / 41), Math.sin(i / 41)] as Point))).toMatch(/at most 256/);
    // A vertex on a non-neighbouring edge.
    expect(polygonProblem([[0, 0], [4, 0], [4, 4], [2, 0], [0, 4]])).toBe('edges cross');
  });
});
