// The trail of the estimated pose: the last TRAIL_LENGTH positions, kept in a ring buffer so a
// long run costs neither memory nor per-pose copying.

import type { MapFrame, MapLayer, Redraw } from '../layer';
import { strokePolyline } from '../shapes';

/** Positions kept in the trail. */
export const TRAIL_LENGTH = 600;
/** A pose closer than this (m) to the last trail point adds nothing (a robot standing still). */
const MIN_STEP_M = 0.02;
const TRAIL_STYLE = { color: 'rgba(250, 204, 21, 0.75)', width: 1.5 };

export class TrailLayer implements MapLayer {
  readonly id = 'trail';
  readonly toggle = 'trail';
  readonly showsRobot = true;
  private readonly xy = new Float64Array(TRAIL_LENGTH * 2);
  /** Ring slot of the oldest point. */
  private start = 0;
  private count = 0;

  constructor(private readonly redraw: Redraw) {}

  /** Appends a position (dropping the oldest once full) unless it is next to the last one. */
  add(x: number, y: number): void {
    const last = this.count > 0 ? (this.start + this.count - 1) % TRAIL_LENGTH : -1;
    const moved = last < 0 || Math.hypot(this.xy[2 * last]! - x, this.xy[2 * last + 1]! - y) > MIN_STEP_M;
    if (!moved) return;
    let slot: number;
    if (this.count < TRAIL_LENGTH) {
      slot = (this.start + this.count) % TRAIL_LENGTH;
      this.count++;
    } else {
      slot = this.start;
      this.start = (this.start + 1) % TRAIL_LENGTH;
    }
    this.xy[2 * slot] = x;
    this.xy[2 * slot + 1] = y;
    this.redraw();
  }

  clear(): void {
    this.start = 0;
    this.count = 0;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    strokePolyline(ctx, view, this.xy, TRAIL_STYLE, { count: this.count, start: this.start, ring: TRAIL_LENGTH });
  }
}
