// The state machine of drawing a polygon on the map (keep-out zones): start, click vertices,
// close with a double click, Enter or a click on the first vertex, cancel with Esc, Backspace takes
// the last vertex back. While the closed polygon is with the server the draft waits ("submitting");
// refused, it is reopened with its vertices so it can be mended. Pure, unit-tested.

import { MAX_POLYGON_VERTICES, MIN_POLYGON_VERTICES, polygonProblem } from './polygon';
import type { Point } from './polygon';

export type DraftState = 'idle' | 'drawing' | 'submitting';

export type DraftResult =
  | { kind: 'added'; vertices: number }
  /** A click on (or next to) the last vertex: the second click of a double click. */
  | { kind: 'ignored' }
  | { kind: 'closed'; polygon: [number, number][] }
  | { kind: 'refused'; reason: string }
  | { kind: 'canceled' }
  | { kind: 'none' };

export class PolygonDraft {
  state: DraftState = 'idle';
  vertices: [number, number][] = [];
  /** The pointer (map frame) while drawing: the rubber-band edge goes there. */
  cursor: [number, number] | null = null;

  get active(): boolean {
    return this.state === 'drawing';
  }

  /** Starts a new polygon (anything drawn before is dropped). */
  start(): void {
    this.state = 'drawing';
    this.vertices = [];
    this.cursor = null;
  }

  /** Esc: drops the draft. */
  cancel(): DraftResult {
    if (this.state === 'idle') return { kind: 'none' };
    this.state = 'idle';
    this.vertices = [];
    this.cursor = null;
    return { kind: 'canceled' };
  }

  /**
   * A click at map point p. `tolerance` (m, a few screen pixels): a click this close to the first
   * vertex closes the polygon (3 or more vertices), one this close to the last is ignored.
   */
  click(p: Point, tolerance: number): DraftResult {
    if (this.state !== 'drawing') return { kind: 'none' };
    const n = this.vertices.length;
    if (n >= MIN_POLYGON_VERTICES && near(this.vertices[0]!, p, tolerance)) return this.close();
    if (n > 0 && near(this.vertices[n - 1]!, p, tolerance)) return { kind: 'ignored' };
    if (n >= MAX_POLYGON_VERTICES) return { kind: 'refused', reason: `a zone has at most ${MAX_POLYGON_VERTICES} vertices: close it (Enter)` };
    this.vertices.push([p[0], p[1]]);
    this.cursor = [p[0], p[1]];
    return { kind: 'added', vertices: this.vertices.length };
  }

  move(p: Point): void {
    if (this.state === 'drawing') this.cursor = [p[0], p[1]];
  }

  /** Enter or a double click: the polygon as drawn goes to the server, unless it has too few vertices. */
  close(): DraftResult {
    if (this.state !== 'drawing') return { kind: 'none' };
    if (this.vertices.length < MIN_POLYGON_VERTICES) {
      const missing = MIN_POLYGON_VERTICES - this.vertices.length;
      return { kind: 'refused', reason: `a zone needs at least ${MIN_POLYGON_VERTICES} vertices: click ${missing} more` };
    }
    // A shape that is not simple is still sent: the server's invalid_polygon message says why.
    this.state = 'submitting';
    this.cursor = null;
    return { kind: 'closed', polygon: this.vertices.map(([x, y]) => [x, y]) };
  }

  /** Backspace: takes the last vertex back. */
  undo(): DraftResult {
    if (this.state !== 'drawing' || this.vertices.length === 0) return { kind: 'none' };
    this.vertices.pop();
    return { kind: 'added', vertices: this.vertices.length };
  }

  /** The server stored the polygon: the draft is done. */
  accepted(): void {
    this.state = 'idle';
    this.vertices = [];
    this.cursor = null;
  }

  /** The server refused the polygon: drawing goes on with its vertices. */
  reopen(): void {
    if (this.state === 'submitting') this.state = 'drawing';
  }

  /** What is wrong with the polygon if it were closed now (null: nothing). */
  get problem(): string | null {
    if (this.state === 'idle' || this.vertices.length === 0) return null;
    return polygonProblem(this.vertices);
  }
}

function near(a: Point, b: Point, tolerance: number): boolean {
  return Math.hypot(a[0] - b[0], a[1] - b[1]) <= tolerance;
}
