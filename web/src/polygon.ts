// Plane polygon geometry for keep-out zones: segment intersection, whether a polygon is simple (no
// two edges cross or touch except neighbours at their shared vertex), area. Pure, unit-tested.

export type Point = readonly [number, number];

/** Vertex counts a keep-out zone may have (the server's rule, checked here before sending). */
export const MIN_POLYGON_VERTICES = 3;
export const MAX_POLYGON_VERTICES = 256;

/** Orientation of c relative to a->b: > 0 left, < 0 right, 0 collinear (within eps). */
function orient(a: Point, b: Point, c: Point, eps: number): number {
  const v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  return Math.abs(v) <= eps ? 0 : Math.sign(v);
}

/** Whether c, collinear with a-b, lies within the segment's box. */
function onSegment(a: Point, b: Point, c: Point): boolean {
  return Math.min(a[0], b[0]) <= c[0] && c[0] <= Math.max(a[0], b[0]) && Math.min(a[1], b[1]) <= c[1] && c[1] <= Math.max(a[1], b[1]);
}

/** Whether segments a-b and c-d share a point (crossing, touching or overlapping). */
export function segmentsIntersect(a: Point, b: Point, c: Point, d: Point, eps = 1e-12): boolean {
  const o1 = orient(a, b, c, eps);
  const o2 = orient(a, b, d, eps);
  const o3 = orient(c, d, a, eps);
  const o4 = orient(c, d, b, eps);
  if (o1 !== o2 && o3 !== o4) return true;
  if (o1 === 0 && onSegment(a, b, c)) return true;
  if (o2 === 0 && onSegment(a, b, d)) return true;
  if (o3 === 0 && onSegment(c, d, a)) return true;
  if (o4 === 0 && onSegment(c, d, b)) return true;
  return false;
}

/** Signed area (positive counter-clockwise), shoelace formula. */
export function signedArea(points: readonly Point[]): number {
  let sum = 0;
  for (let i = 0; i < points.length; i++) {
    const [x0, y0] = points[i]!;
    const [x1, y1] = points[(i + 1) % points.length]!;
    sum += x0 * y1 - x1 * y0;
  }
  return sum / 2;
}

export function polygonArea(points: readonly Point[]): number {
  return Math.abs(signedArea(points));
}

/** Why the closed polygon is not simple, or null when it is (>= 3 vertices, no repeated vertex, no crossing, some area). */
export function polygonProblem(points: readonly Point[]): string | null {
  const n = points.length;
  if (n < MIN_POLYGON_VERTICES) return `a zone needs at least ${MIN_POLYGON_VERTICES} vertices`;
  if (n > MAX_POLYGON_VERTICES) return `a zone has at most ${MAX_POLYGON_VERTICES} vertices`;
  for (let i = 0; i < n; i++) {
    const a = points[i]!;
    const b = points[(i + 1) % n]!;
    if (a[0] === b[0] && a[1] === b[1]) return 'two consecutive vertices coincide';
  }
  // Every pair of edges that are not neighbours must be disjoint; neighbours share only their vertex.
  for (let i = 0; i < n; i++) {
    const a = points[i]!;
    const b = points[(i + 1) % n]!;
    for (let j = i + 1; j < n; j++) {
      const c = points[j]!;
      const d = points[(j + 1) % n]!;
      const neighbours = j === i + 1 || (i === 0 && j === n - 1);
      if (neighbours) {
        // Neighbours share one vertex; they fold back when the other two ends lie on one ray from it.
        const [shared, far1, far2] = j === i + 1 ? [b, a, d] : [a, b, c];
        const dot = (far1[0] - shared[0]) * (far2[0] - shared[0]) + (far1[1] - shared[1]) * (far2[1] - shared[1]);
        if (orient(shared, far1, far2, 1e-12) === 0 && dot > 0) return 'an edge folds back onto its neighbour';
        continue;
      }
      if (segmentsIntersect(a, b, c, d)) return 'edges cross';
    }
  }
  if (polygonArea(points) <= 1e-12) return 'the zone has no area';
  return null;
}

export function isSimplePolygon(points: readonly Point[]): boolean {
  return polygonProblem(points) === null;
}
