// The preview of the active press-and-drag tool: at the cursor before the press (hollow), at the
// press point while pressed (filled), with the drag's heading as an arrow and degrees when the
// tool takes a heading, and the obstacle's circle when it has a radius.

import { dragHeading } from '../../goals';
import type { MapTool, ToolPress } from '../input';
import type { MapFrame, MapLayer } from '../layer';
import { drawArrow } from '../shapes';

/** Shortest heading arrow (px), so a drag just past the threshold still shows a clear arrow. */
const MIN_ARROW_PX = 20;

export class ToolPreviewLayer implements MapLayer {
  readonly id = 'toolPreview';

  draw(frame: MapFrame): void {
    const { tool, press, cursor } = frame.scene.pointer;
    if (!tool || tool.ownPreview) return;
    const at = press ? [press.x, press.y] : cursor;
    if (!at) return;
    const [sx, sy] = frame.view.toScreen(at[0]!, at[1]!);
    drawMarker(frame, tool, press !== null, sx, sy);
    if (press && tool.heading) drawDragHeading(frame, tool, press, sx, sy);
  }
}

function drawMarker({ ctx, view }: MapFrame, tool: MapTool, pressed: boolean, sx: number, sy: number): void {
  ctx.strokeStyle = tool.color;
  ctx.fillStyle = tool.color;
  ctx.lineWidth = 2;
  if (tool.radius !== undefined) {
    ctx.setLineDash(pressed ? [] : [4, 3]);
    ctx.beginPath();
    ctx.arc(sx, sy, Math.max(3, tool.radius * view.scale), 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    return;
  }
  ctx.beginPath();
  ctx.arc(sx, sy, pressed ? 6 : 4, 0, 2 * Math.PI);
  if (pressed) ctx.fill();
  else ctx.stroke();
}

function drawDragHeading({ ctx, view }: MapFrame, tool: MapTool, press: ToolPress, sx: number, sy: number): void {
  const heading = dragHeading(press, { x: press.currentX, y: press.currentY }, view.scale);
  if (heading === null) return;
  const length = Math.hypot(press.currentX - press.x, press.currentY - press.y) * view.scale;
  drawArrow(ctx, sx, sy, heading, Math.max(length, MIN_ARROW_PX), { color: tool.color, width: 2.5 });
  ctx.font = '600 11px system-ui, sans-serif';
  ctx.fillStyle = tool.color;
  ctx.fillText(`${((heading * 180) / Math.PI).toFixed(0)}°`, sx + 10, sy - 10);
}
