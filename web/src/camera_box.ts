// Drawing a box on the camera image to pick a target: press, drag, release. The pointer's client
// (CSS) coordinates are mapped to pixels of the camera image whatever size the panel shows it at
// (the image is fitted into its element as `object-fit: contain` would, centred), the corners are
// clipped to the image, and the box is normalised whichever way the drag went. A click without a
// drag sends nothing; a box narrower or lower than MIN_BOX_PX image pixels is refused. Pure (no
// DOM): unit-tested; camera_panel.ts feeds it pointer events.

/** A box in image pixels: top-left corner, width, height (the body of POST /api/v1/tracking). */
export interface ImageBox {
  x: number;
  y: number;
  w: number;
  h: number;
}

/** An element's box in client coordinates (what getBoundingClientRect gives). */
export interface ClientRect {
  left: number;
  top: number;
  width: number;
  height: number;
}

export type ImagePoint = [number, number];

/** Smaller than this (image pixels, either side) is no target: refused here. */
export const MIN_BOX_PX = 8;
/** A press released within this many CSS pixels of where it started is a click, not a box. */
export const CLICK_SLOP_PX = 4;

/** Where an image of imageW x imageH pixels is shown inside `rect`: fitted whole, centred (object-fit: contain). */
export function contentRect(rect: ClientRect, imageW: number, imageH: number): ClientRect {
  if (!(imageW > 0 && imageH > 0 && rect.width > 0 && rect.height > 0)) return { ...rect };
  const scale = Math.min(rect.width / imageW, rect.height / imageH);
  const width = imageW * scale;
  const height = imageH * scale;
  return { left: rect.left + (rect.width - width) / 2, top: rect.top + (rect.height - height) / 2, width, height };
}

/** Client coordinates -> image pixels (continuous: pixel i spans [i, i+1)); not clipped. */
export function clientToImage(clientX: number, clientY: number, rect: ClientRect, imageW: number, imageH: number): ImagePoint {
  const content = contentRect(rect, imageW, imageH);
  if (!(content.width > 0 && content.height > 0)) return [0, 0];
  return [((clientX - content.left) / content.width) * imageW, ((clientY - content.top) / content.height) * imageH];
}

/** Image pixels -> client coordinates (the inverse of clientToImage; for drawing and the browser test). */
export function imageToClient(x: number, y: number, rect: ClientRect, imageW: number, imageH: number): [number, number] {
  const content = contentRect(rect, imageW, imageH);
  if (!(imageW > 0 && imageH > 0)) return [content.left, content.top];
  return [content.left + (x / imageW) * content.width, content.top + (y / imageH) * content.height];
}

/** Whether an image point lies on the image. */
export function onImage([x, y]: ImagePoint, imageW: number, imageH: number): boolean {
  return x >= 0 && y >= 0 && x <= imageW && y <= imageH;
}

const clip = (v: number, hi: number) => Math.min(hi, Math.max(0, v));

/**
 * The box spanned by two corners, in any order, clipped to the image and snapped outwards to whole
 * pixels (the server gets integers).
 */
export function boxFromCorners(a: ImagePoint, b: ImagePoint, imageW: number, imageH: number): ImageBox {
  const x0 = Math.floor(clip(Math.min(a[0], b[0]), imageW));
  const y0 = Math.floor(clip(Math.min(a[1], b[1]), imageH));
  const x1 = Math.ceil(clip(Math.max(a[0], b[0]), imageW));
  const y1 = Math.ceil(clip(Math.max(a[1], b[1]), imageH));
  return { x: x0, y: y0, w: Math.max(0, x1 - x0), h: Math.max(0, y1 - y0) };
}

/** Why a box cannot be a target, or null when it can. */
export function boxProblem(box: ImageBox, minPx = MIN_BOX_PX): string | null {
  if (box.w < minPx || box.h < minPx) {
    return `The box is ${box.w}×${box.h} px: draw one at least ${minPx}×${minPx} px around the target.`;
  }
  return null;
}

export type BoxResult =
  /** Nothing was being drawn. */
  | { kind: 'none' }
  /** Released where it was pressed: no box, nothing to send. */
  | { kind: 'click' }
  | { kind: 'canceled' }
  | { kind: 'refused'; box: ImageBox; reason: string }
  | { kind: 'box'; box: ImageBox };

/** The box being drawn: press, move, release (or cancel). */
export class BoxDraft {
  /** Corners in image pixels, clipped to the image. */
  start: ImagePoint | null = null;
  end: ImagePoint | null = null;
  private startClient: [number, number] = [0, 0];
  /** Farthest the pointer went from the press (CSS pixels). */
  private travel = 0;
  private imageW = 0;
  private imageH = 0;

  get active(): boolean {
    return this.start !== null;
  }

  /** A press at client (x, y) on an element showing an image of imageW x imageH; false (and no draft) off the image. */
  press(clientX: number, clientY: number, rect: ClientRect, imageW: number, imageH: number): boolean {
    const p = clientToImage(clientX, clientY, rect, imageW, imageH);
    if (!(imageW > 0 && imageH > 0) || !onImage(p, imageW, imageH)) {
      this.reset();
      return false;
    }
    this.imageW = imageW;
    this.imageH = imageH;
    this.start = p;
    this.end = p;
    this.startClient = [clientX, clientY];
    this.travel = 0;
    return true;
  }

  /** The pointer moved (anywhere: the corner is clipped to the image). */
  move(clientX: number, clientY: number, rect: ClientRect): void {
    if (!this.start) return;
    const [x, y] = clientToImage(clientX, clientY, rect, this.imageW, this.imageH);
    this.end = [clip(x, this.imageW), clip(y, this.imageH)];
    this.travel = Math.max(this.travel, Math.hypot(clientX - this.startClient[0], clientY - this.startClient[1]));
  }

  /** Released at client (x, y): the box to send, a click, or a refusal. */
  release(clientX: number, clientY: number, rect: ClientRect): BoxResult {
    if (!this.start) return { kind: 'none' };
    this.move(clientX, clientY, rect);
    const box = this.box!;
    const travel = this.travel;
    this.reset();
    if (travel < CLICK_SLOP_PX) return { kind: 'click' };
    const reason = boxProblem(box);
    return reason ? { kind: 'refused', box, reason } : { kind: 'box', box };
  }

  cancel(): BoxResult {
    if (!this.start) return { kind: 'none' };
    this.reset();
    return { kind: 'canceled' };
  }

  /** The box drawn so far (image pixels), or null. */
  get box(): ImageBox | null {
    if (!this.start || !this.end) return null;
    return boxFromCorners(this.start, this.end, this.imageW, this.imageH);
  }

  private reset(): void {
    this.start = null;
    this.end = null;
    this.travel = 0;
  }
}
