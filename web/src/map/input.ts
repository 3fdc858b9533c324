// Pointer input on the map canvas: drag pans, the wheel zooms about the cursor, a double click
// fits, and while a tool is active (set goal, set pose, drop obstacle: press and drag; keep-out
// zone: click vertices, double-click to close) a left press belongs to the tool instead of
// panning. The cursor's map position is kept for the readout.

import { dragHeading } from '../goals';
import type { Viewport } from './viewport';
import { wheelZoomFactor } from './view_transform';

/**
 * A press-and-drag tool on the map. `done` gets the press point and, when the pointer was dragged,
 * the heading of the drag (map frame).
 */
export interface MapTool {
  name: string;
  color: string;
  /** Whether a drag sets a heading (arrow preview). */
  heading: boolean;
  /** A circle of this radius (m) is previewed at the press point (obstacles). */
  radius?: number;
  /** The tool draws its own preview (a polygon draft): no marker at the cursor. */
  ownPreview?: boolean;
  /** A release: the press point and, for heading tools dragged far enough, the drag's heading. */
  done(point: { x: number; y: number }, heading: number | null): void;
  /** A double click while the tool is active; without it a double click does nothing then. */
  doubleClick?(point: { x: number; y: number }): void;
  /** The pointer moved over the canvas (map frame). */
  moved?(point: { x: number; y: number }): void;
  /** Another tool (or none) replaced this one. */
  left?(): void;
}

/** A tool's press in progress: where it went down and where the pointer is now (map frame). */
export interface ToolPress {
  pointerId: number;
  x: number;
  y: number;
  currentX: number;
  currentY: number;
}

/** What the tool preview and the cursor readout draw. */
export interface PointerState {
  tool: MapTool | null;
  press: ToolPress | null;
  /** Map position under the pointer, null once it left the canvas. */
  cursor: [number, number] | null;
}

export interface InputHooks {
  /** Something drawn changed (view, cursor, press). */
  redraw(): void;
  /** A double click outside a tool: fit the content. */
  fit(): void;
}

/** A pan drag in progress, in client pixels. */
interface PanDrag {
  pointerId: number;
  clientX: number;
  clientY: number;
}

export class MapInput {
  readonly pointer: PointerState = { tool: null, press: null, cursor: null };
  private pan: PanDrag | null = null;

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly viewport: Viewport,
    private readonly hooks: InputHooks,
  ) {
    canvas.addEventListener('pointerdown', (e) => this.onPointerDown(e));
    canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
    canvas.addEventListener('pointerup', (e) => this.onPointerUp(e));
    canvas.addEventListener('pointercancel', (e) => this.onPointerCancel(e));
    canvas.addEventListener('pointerleave', () => this.onPointerLeave());
    // Not passive: the wheel zooms the map instead of scrolling the page.
    canvas.addEventListener('wheel', (e) => this.onWheel(e), { passive: false });
    canvas.addEventListener('dblclick', (e) => {
      const tool = this.pointer.tool;
      if (!tool) hooks.fit();
      else if (tool.doubleClick) {
        const [x, y] = this.mapPoint(e);
        tool.doubleClick({ x, y });
        hooks.redraw();
      }
    });
  }

  /** Activates a press-and-drag tool (null: back to panning); a press in progress is dropped. */
  setTool(tool: MapTool | null): void {
    const press = this.pointer.press;
    if (press) this.release(press.pointerId);
    const previous = this.pointer.tool;
    this.pointer.tool = tool;
    if (previous && previous !== tool) previous.left?.();
    this.pointer.press = null;
    this.canvas.classList.toggle('tool', !!tool);
    this.hooks.redraw();
  }

  private onPointerDown(e: PointerEvent): void {
    if (e.button !== 0) return;
    if (this.pointer.tool) {
      const [x, y] = this.mapPoint(e);
      this.pointer.press = { pointerId: e.pointerId, x, y, currentX: x, currentY: y };
      this.canvas.setPointerCapture(e.pointerId);
      this.hooks.redraw();
      return;
    }
    this.pan = { pointerId: e.pointerId, clientX: e.clientX, clientY: e.clientY };
    this.canvas.setPointerCapture(e.pointerId);
    this.canvas.classList.add('dragging');
  }

  private onPointerMove(e: PointerEvent): void {
    const cursor = this.mapPoint(e);
    this.pointer.cursor = cursor;
    this.pointer.tool?.moved?.({ x: cursor[0], y: cursor[1] });
    const press = this.pointer.press;
    if (press && press.pointerId === e.pointerId) {
      press.currentX = cursor[0];
      press.currentY = cursor[1];
    } else if (this.pan && this.pan.pointerId === e.pointerId) {
      this.viewport.panBy(e.clientX - this.pan.clientX, e.clientY - this.pan.clientY);
      this.pan.clientX = e.clientX;
      this.pan.clientY = e.clientY;
    }
    this.hooks.redraw();
  }

  private onPointerUp(e: PointerEvent): void {
    const { press, tool } = this.pointer;
    if (press && press.pointerId === e.pointerId && tool) {
      const [x, y] = this.mapPoint(e);
      this.pointer.press = null;
      this.hooks.redraw();
      const heading = tool.heading ? dragHeading(press, { x, y }, this.viewport.transform.scale) : null;
      tool.done({ x: press.x, y: press.y }, heading);
      return;
    }
    this.endPan(e);
  }

  private onPointerCancel(e: PointerEvent): void {
    if (this.pointer.press && this.pointer.press.pointerId === e.pointerId) {
      this.pointer.press = null;
      this.hooks.redraw();
    }
    this.endPan(e);
  }

  private onPointerLeave(): void {
    this.pointer.cursor = null;
    this.hooks.redraw();
  }

  private onWheel(e: WheelEvent): void {
    e.preventDefault();
    const [sx, sy] = this.canvasPoint(e);
    this.viewport.zoomAbout(sx, sy, wheelZoomFactor(e.deltaY, e.deltaMode));
    this.hooks.redraw();
  }

  private endPan(e: PointerEvent): void {
    if (this.pan && this.pan.pointerId === e.pointerId) {
      this.pan = null;
      this.canvas.classList.remove('dragging');
    }
  }

  private release(pointerId: number): void {
    try {
      this.canvas.releasePointerCapture(pointerId);
    } catch {
      // the pointer was not captured (already released)
    }
  }

  /** CSS pixels relative to the canvas. */
  private canvasPoint(e: MouseEvent): [number, number] {
    const rect = this.canvas.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  }

  private mapPoint(e: MouseEvent): [number, number] {
    const [sx, sy] = this.canvasPoint(e);
    return this.viewport.transform.toWorld(sx, sy);
  }
}
