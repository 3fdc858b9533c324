// The map's <canvas>: its 2D context, its CSS size and device pixel ratio, and the draw loop. The
// backing store follows the CSS size times the device pixel ratio so lines stay sharp; frames are
// drawn at most once per animation frame and only after invalidate(), always with the latest data.

export interface CanvasHooks {
  /** The canvas was laid out at a new CSS size (never 0 x 0: hidden canvases keep their size). */
  resized(width: number, height: number): void;
  /** Draw a frame now. */
  render(): void;
}

export class MapCanvas {
  readonly ctx: CanvasRenderingContext2D;
  /** Device pixels per CSS pixel of the current backing store. */
  dpr = 1;
  /** CSS pixels. */
  width = 0;
  height = 0;
  private dirty = true;
  private frameRequest = 0;
  private readonly resizeObserver: ResizeObserver;

  constructor(
    readonly element: HTMLCanvasElement,
    private readonly hooks: CanvasHooks,
  ) {
    const ctx = element.getContext('2d', { alpha: false });
    if (!ctx) throw new Error('canvas 2D is not available');
    this.ctx = ctx;
    this.resizeObserver = new ResizeObserver(() => this.measure());
    this.resizeObserver.observe(element);
  }

  /** Measures the canvas and draws the first frame; called once the owner can render. */
  start(): void {
    this.measure();
    this.loop();
  }

  destroy(): void {
    cancelAnimationFrame(this.frameRequest);
    this.resizeObserver.disconnect();
  }

  /** Asks for a frame at the next animation frame. */
  invalidate(): void {
    this.dirty = true;
  }

  /** Fills the whole backing store (device pixels, whatever the current transform). */
  clear(color: string): void {
    this.ctx.setTransform(1, 0, 0, 1, 0, 0);
    this.ctx.fillStyle = color;
    this.ctx.fillRect(0, 0, this.element.width, this.element.height);
  }

  private readonly loop = (): void => {
    this.frameRequest = requestAnimationFrame(this.loop);
    // Polled as well as observed: a device pixel ratio change (browser zoom) resizes nothing.
    this.measure();
    if (!this.dirty) return;
    this.dirty = false;
    this.hooks.render();
  };

  private measure(): void {
    const rect = this.element.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const width = Math.round(rect.width);
    const height = Math.round(rect.height);
    // A hidden page (display: none) has no size: keep the view as it was until it is shown again.
    if (width < 2 || height < 2) return;
    if (width === this.width && height === this.height && dpr === this.dpr) return;
    this.hooks.resized(width, height);
    this.width = width;
    this.height = height;
    this.dpr = dpr;
    this.element.width = Math.max(1, Math.round(width * dpr));
    this.element.height = Math.max(1, Math.round(height * dpr));
    this.dirty = true;
  }
}
