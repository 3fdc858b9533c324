// The goal marker: a ring and dot at the target, an arrow for a requested heading, a cross when
// the goal failed; coloured by status and faded once the goal has ended.

import type { GoalStatus } from '../../goals';
import { CASING, STATUS_COLORS } from '../colors';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawArrow, strokeCross } from '../shapes';
import { PATH_COLOR } from './path';

/** The goal marker: target and, when given, the requested heading. */
export interface GoalMarker {
  x: number;
  y: number;
  theta?: number;
  status: GoalStatus;
}

const ENDED_ALPHA = 0.6;

export class GoalLayer implements MapLayer {
  readonly id = 'goal';
  private goal: GoalMarker | null = null;

  constructor(private readonly redraw: Redraw) {}

  set(goal: GoalMarker | null): void {
    this.goal = goal;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    const goal = this.goal;
    if (!goal) return;
    const [sx, sy] = view.toScreen(goal.x, goal.y);
    const color = STATUS_COLORS[goal.status] ?? PATH_COLOR;
    const ended = goal.status === 'succeeded' || goal.status === 'failed' || goal.status === 'canceled';
    // Grows with the zoom, within limits that keep it a marker rather than a region.
    const r = Math.max(7, Math.min(14, 0.18 * view.scale));
    ctx.globalAlpha = ended ? ENDED_ALPHA : 1;
    drawTarget(ctx, sx, sy, r, color);
    if (goal.theta !== undefined) drawArrow(ctx, sx, sy, goal.theta, r + Math.max(14, 0.45 * view.scale), { color, width: 2.5 });
    if (goal.status === 'failed') {
      ctx.strokeStyle = color;
      ctx.lineWidth = 2;
      strokeCross(ctx, sx, sy, r * 0.55);
    }
    ctx.globalAlpha = 1;
  }
}

/** A flag-like target: a cased ring of radius r and a dot. */
function drawTarget(ctx: CanvasRenderingContext2D, sx: number, sy: number, r: number, color: string): void {
  ctx.lineWidth = 2.5;
  ctx.strokeStyle = CASING;
  ctx.beginPath();
  ctx.arc(sx, sy, r + 1.5, 0, 2 * Math.PI);
  ctx.stroke();
  ctx.strokeStyle = color;
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.arc(sx, sy, r, 0, 2 * Math.PI);
  ctx.stroke();
  ctx.fillStyle = color;
  ctx.beginPath();
  ctx.arc(sx, sy, 3, 0, 2 * Math.PI);
  ctx.fill();
}
