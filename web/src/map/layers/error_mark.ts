// A red cross where the map refused a point (a goal in a wall, an obstacle off the map), shown for
// a few seconds.

import { CASING } from '../colors';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { strokeCross } from '../shapes';

const CROSS_COLOR = '#f87171';
const CROSS_HALF_PX = 8;
const DEFAULT_SHOW_MS = 4000;

export class ErrorMarkLayer implements MapLayer {
  readonly id = 'errorMark';
  private mark: { x: number; y: number; until: number } | null = null;

  constructor(private readonly redraw: Redraw) {}

  /** Marks map point (x, y) for `ms` milliseconds. */
  flash(x: number, y: number, ms = DEFAULT_SHOW_MS): void {
    this.mark = { x, y, until: performance.now() + ms };
    this.redraw();
    // A still map draws no frames: ask for one just after the expiry so the cross goes away.
    window.setTimeout(() => this.redraw(), ms + 20);
  }

  draw({ ctx, view }: MapFrame): void {
    const mark = this.mark;
    if (!mark) return;
    if (performance.now() > mark.until) {
      this.mark = null;
      return;
    }
    const [sx, sy] = view.toScreen(mark.x, mark.y);
    ctx.strokeStyle = CASING;
    ctx.lineWidth = 5;
    strokeCross(ctx, sx, sy, CROSS_HALF_PX);
    ctx.strokeStyle = CROSS_COLOR;
    ctx.lineWidth = 2.5;
    strokeCross(ctx, sx, sy, CROSS_HALF_PX);
  }
}
