import { describe, expect, it } from 'vitest';
import { BoxDraft, boxFromCorners, boxProblem, clientToImage, contentRect, imageToClient, MIN_BOX_PX } from '../src/camera_box';

// A 640 x 480 image shown at half size, 320 x 240 CSS pixels, at (100, 50) in the viewport.
const RECT = { left: 100, top: 50, width: 320, height: 240 };
const W = 640;
const H = 480;

describe('client -> image pixels', () => {
  it('scales a panel shown smaller than the image', () => {
    expect(clientToImage(100, 50, RECT, W, H)).toEqual([0, 0]);
    expect(clientToImage(260, 170, RECT, W, H)).toEqual([320, 240]);
    expect(clientToImage(420, 290, RECT, W, H)).toEqual([640, 480]);
    // And larger (the enlarged view).
    expect(clientToImage(10 + 960, 20 + 720, { left: 10, top: 20, width: 1280, height: 960 }, W, H)).toEqual([480, 360]);
  });

  it('fits the image into an element of another shape (letterboxed, centred)', () => {
    const wide = { left: 0, top: 0, width: 400, height: 240 };
    expect(contentRect(wide, W, H)).toEqual({ left: 40, top: 0, width: 320, height: 240 });
    expect(clientToImage(40, 0, wide, W, H)).toEqual([0, 0]);
    expect(clientToImage(360, 240, wide, W, H)).toEqual([640, 480]);
    const tall = { left: 0, top: 0, width: 320, height: 400 };
    expect(contentRect(tall, W, H)).toEqual({ left: 0, top: 80, width: 320, height: 240 });
  });

  it('goes back with imageToClient', () => {
    const [cx, cy] = imageToClient(123, 321, RECT, W, H);
    const [x, y] = clientToImage(cx, cy, RECT, W, H);
    expect(x).toBeCloseTo(123);
    expect(y).toBeCloseTo(321);
  });
});

describe('boxes', () => {
  it('normalise corners in any order and snap outwards to whole pixels', () => {
    const expected = { x: 10, y: 20, w: 90, h: 60 };
    expect(boxFromCorners([10, 20], [100, 80], W, H)).toEqual(expected);
    expect(boxFromCorners([100, 80], [10, 20], W, H)).toEqual(expected);
    expect(boxFromCorners([10, 80], [100, 20], W, H)).toEqual(expected);
    expect(boxFromCorners([100, 20], [10, 80], W, H)).toEqual(expected);
    expect(boxFromCorners([10.6, 20.2], [99.1, 79.9], W, H)).toEqual(expected);
  });

  it('clip to the image', () => {
    expect(boxFromCorners([-50, -10], [30, 40], W, H)).toEqual({ x: 0, y: 0, w: 30, h: 40 });
    expect(boxFromCorners([600, 450], [900, 700], W, H)).toEqual({ x: 600, y: 450, w: 40, h: 30 });
    expect(boxFromCorners([700, 10], [800, 40], W, H)).toEqual({ x: 640, y: 10, w: 0, h: 30 });
  });

  it(`refuse less than ${MIN_BOX_PX} px either way`, () => {
    expect(boxProblem({ x: 0, y: 0, w: 7, h: 50 })).toMatch(/7×50 px/);
    expect(boxProblem({ x: 0, y: 0, w: 50, h: 3 })).toMatch(/at least 8×8/);
    expect(boxProblem({ x: 0, y: 0, w: 8, h: 8 })).toBeNull();
  });
});

describe('drawing a box with the mouse', () => {
  it('maps a drag on the half-size panel to image pixels', () => {
    const d = new BoxDraft();
    expect(d.press(150, 100, RECT, W, H)).toBe(true);
    d.move(200, 140, RECT);
    expect(d.box).toEqual({ x: 100, y: 100, w: 100, h: 80 });
    expect(d.release(250, 150, RECT)).toEqual({ kind: 'box', box: { x: 100, y: 100, w: 200, h: 100 } });
    expect(d.active).toBe(false);
  });

  it('accepts drags in any direction', () => {
    const d = new BoxDraft();
    d.press(250, 150, RECT, W, H);
    d.move(200, 120, RECT);
    expect(d.release(150, 100, RECT)).toEqual({ kind: 'box', box: { x: 100, y: 100, w: 200, h: 100 } });
    d.press(150, 150, RECT, W, H);
    expect(d.release(250, 100, RECT)).toEqual({ kind: 'box', box: { x: 100, y: 100, w: 200, h: 100 } });
    d.press(250, 100, RECT, W, H);
    expect(d.release(150, 150, RECT)).toEqual({ kind: 'box', box: { x: 100, y: 100, w: 200, h: 100 } });
  });

  it('clips a drag that leaves the image', () => {
    const d = new BoxDraft();
    d.press(400, 270, RECT, W, H);
    d.move(900, 900, RECT);
    expect(d.box).toEqual({ x: 600, y: 440, w: 40, h: 40 });
    expect(d.release(1000, 1000, RECT)).toEqual({ kind: 'box', box: { x: 600, y: 440, w: 40, h: 40 } });
  });

  it('sends nothing for a click without a drag', () => {
    const d = new BoxDraft();
    d.press(200, 100, RECT, W, H);
    d.move(201, 101, RECT);
    expect(d.release(202, 101, RECT)).toEqual({ kind: 'click' });
    expect(d.release(202, 101, RECT)).toEqual({ kind: 'none' });
  });

  it('refuses a tiny box', () => {
    const d = new BoxDraft();
    d.press(200, 100, RECT, W, H);
    // 3 CSS px = 6 image px across: dragged, but too small.
    const result = d.release(203, 110, RECT);
    expect(result.kind).toBe('refused');
    if (result.kind === 'refused') {
      expect(result.box).toEqual({ x: 200, y: 100, w: 6, h: 20 });
      expect(result.reason).toMatch(/6×20 px/);
    }
  });

  it('does not start off the image (letterbox) and can be canceled', () => {
    const d = new BoxDraft();
    const wide = { left: 0, top: 0, width: 400, height: 240 };
    expect(d.press(20, 100, wide, W, H)).toBe(false);
    expect(d.active).toBe(false);
    expect(d.press(100, 100, wide, W, H)).toBe(true);
    expect(d.cancel()).toEqual({ kind: 'canceled' });
    expect(d.box).toBeNull();
    expect(d.press(100, 100, wide, 0, 0)).toBe(false);
  });
});
