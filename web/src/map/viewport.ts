// The view transform of one map canvas together with the canvas size and the framing policy: the
// view fits the content (map, or the robot's surroundings) until the user pans or zooms, and a new
// map only refits a view the user has not moved. Pure (no DOM), like ViewTransform.

import { ViewTransform } from './view_transform';
import type { Bounds } from './view_transform';

/** Pixels kept free around fitted content. */
const FIT_MARGIN_PX = 24;

export class Viewport {
  readonly transform = new ViewTransform();
  /** CSS pixels; 0 until the canvas was first laid out. */
  width = 0;
  height = 0;
  private fitPending = true;
  private movedByUser = false;

  /** A hidden canvas (display: none) measures 0 x 0 and cannot be fitted. */
  get hasSize(): boolean {
    return this.width >= 2 && this.height >= 2;
  }

  /** The canvas was laid out at a new size: the centre of the view stays where it was. */
  resize(width: number, height: number): void {
    if (this.width > 0 && this.height > 0) this.transform.panBy((width - this.width) / 2, (height - this.height) / 2);
    this.width = width;
    this.height = height;
  }

  /** Fit the content at the next draw and follow it again (the Fit button, a double click). */
  requestFit(): void {
    this.movedByUser = false;
    this.fitPending = true;
  }

  /** The content changed shape (another map): refit unless the user has moved the view. */
  contentChanged(): void {
    if (!this.movedByUser) this.fitPending = true;
  }

  /** Fits `content()` if a fit is pending and the canvas has a size; `content` is only asked then. */
  applyPendingFit(content: () => Bounds | null): void {
    if (!this.fitPending || !this.hasSize) return;
    const bounds = content();
    if (!bounds) return;
    this.fitNow(bounds);
    this.fitPending = false;
  }

  /** Shows `bounds` now, without changing whether the view follows the content. */
  fitNow(bounds: Bounds): void {
    if (!this.hasSize) return;
    this.transform.fit(bounds, this.width, this.height, FIT_MARGIN_PX);
  }

  /** A drag by the user, in screen pixels. */
  panBy(dx: number, dy: number): void {
    this.transform.panBy(dx, dy);
    this.movedByUser = true;
  }

  /** A zoom by the user that keeps the map point under screen point (sx, sy) in place. */
  zoomAbout(sx: number, sy: number, factor: number): void {
    this.transform.zoomAbout(sx, sy, factor);
    this.movedByUser = true;
  }

  /** A zoom by the user about the centre of the canvas (toolbar buttons). */
  zoomAtCentre(factor: number): void {
    this.zoomAbout(this.width / 2, this.height / 2, factor);
  }

  /** Puts map point (x, y) at the centre of the canvas. */
  centerOn(x: number, y: number): void {
    this.transform.originX = this.width / 2 - x * this.transform.scale;
    this.transform.originY = this.height / 2 + y * this.transform.scale;
    this.movedByUser = true;
  }

  /** Whether map point (x, y) is inside the canvas. */
  shows(x: number, y: number): boolean {
    if (!this.hasSize) return false;
    const [sx, sy] = this.transform.toScreen(x, y);
    return sx >= 0 && sy >= 0 && sx <= this.width && sy <= this.height;
  }
}
