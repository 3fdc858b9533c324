import { describe, expect, it } from 'vitest';
import { MAX_SCALE, MIN_SCALE, ViewTransform } from '../src/map/view_transform';
import { Viewport } from '../src/map/viewport';

/** Transforms reached the ways the dashboard reaches them: constructed, panned, zoomed, fitted. */
function sampleTransforms(): ViewTransform[] {
  const panned = new ViewTransform(37, -120, 480);
  panned.panBy(-313.5, 91.25);
  const zoomed = new ViewTransform(40, 10, 300);
  zoomed.zoomAbout(512, 384, 0.137);
  const fitted = new ViewTransform();
  fitted.fit({ minX: -12.5, minY: 3, maxX: 40, maxY: 18.2 }, 1280, 720, 24);
  return [new ViewTransform(), new ViewTransform(MIN_SCALE, 0.5, -7), new ViewTransform(MAX_SCALE, 900, 20), panned, zoomed, fitted];
}

const MAP_POINTS: [number, number][] = [
  [0, 0],
  [1.25, -3.5],
  [-250.75, 99.125],
  [1e4, -1e4],
];

describe('ViewTransform round trip', () => {
  it('map -> screen -> map returns the map point', () => {
    for (const view of sampleTransforms()) {
      for (const [x, y] of MAP_POINTS) {
        const [sx, sy] = view.toScreen(x, y);
        const [bx, by] = view.toWorld(sx, sy);
        expect(bx).toBeCloseTo(x, 6);
        expect(by).toBeCloseTo(y, 6);
      }
    }
  });

  it('screen -> map -> screen returns the screen point', () => {
    for (const view of sampleTransforms()) {
      for (const [sx, sy] of [[0, 0], [640, 360], [-33.3, 1999.9]] as const) {
        const [x, y] = view.toWorld(sx, sy);
        const [bx, by] = view.toScreen(x, y);
        expect(bx).toBeCloseTo(sx, 6);
        expect(by).toBeCloseTo(sy, 6);
      }
    }
  });

  it('the single-axis helpers agree with toScreen', () => {
    const view = new ViewTransform(55, 12, 640);
    expect([view.toScreenX(3.5), view.toScreenY(-2)]).toEqual(view.toScreen(3.5, -2));
  });
});

describe('ViewTransform zoom about a point', () => {
  it('keeps the map point under the zoom centre in place, in and out', () => {
    for (const factor of [1.4, 1 / 1.4, 3, 0.2]) {
      for (const view of sampleTransforms()) {
        for (const [sx, sy] of [[0, 0], [237, 81], [1280, 720]] as const) {
          const before = view.toWorld(sx, sy);
          view.zoomAbout(sx, sy, factor);
          const after = view.toScreen(before[0], before[1]);
          expect(after[0]).toBeCloseTo(sx, 6);
          expect(after[1]).toBeCloseTo(sy, 6);
        }
      }
    }
  });

  it('keeps the point in place when the zoom is clamped', () => {
    const view = new ViewTransform(MAX_SCALE / 2, 40, 60);
    const before = view.toWorld(300, 200);
    view.zoomAbout(300, 200, 10);
    expect(view.scale).toBe(MAX_SCALE);
    const [sx, sy] = view.toScreen(before[0], before[1]);
    expect(sx).toBeCloseTo(300, 6);
    expect(sy).toBeCloseTo(200, 6);
  });

  it('zooming in and back out restores the transform', () => {
    const view = new ViewTransform(40, 10, 300);
    view.zoomAbout(100, 50, 2.5);
    view.zoomAbout(100, 50, 1 / 2.5);
    expect(view.scale).toBeCloseTo(40, 9);
    expect(view.originX).toBeCloseTo(10, 9);
    expect(view.originY).toBeCloseTo(300, 9);
  });
});

describe('Viewport', () => {
  const content = { minX: 0, minY: 0, maxX: 10, maxY: 5 };

  function sized(width = 800, height = 600): Viewport {
    const viewport = new Viewport();
    viewport.resize(width, height);
    return viewport;
  }

  it('fits the content once it has a size, and only then asks for it', () => {
    const viewport = new Viewport();
    let asked = 0;
    const bounds = () => {
      asked++;
      return content;
    };
    viewport.applyPendingFit(bounds);
    expect(asked).toBe(0);
    viewport.resize(800, 600);
    viewport.applyPendingFit(bounds);
    viewport.applyPendingFit(bounds);
    expect(asked).toBe(1);
    const [cx, cy] = viewport.transform.toScreen(5, 2.5);
    expect(cx).toBeCloseTo(400);
    expect(cy).toBeCloseTo(300);
  });

  it('keeps the fit pending while there is no content yet', () => {
    const viewport = sized();
    viewport.applyPendingFit(() => null);
    viewport.applyPendingFit(() => content);
    expect(viewport.transform.toScreen(5, 2.5)[0]).toBeCloseTo(400);
  });

  it('does not refit for new content after the user panned, until asked to fit', () => {
    const viewport = sized();
    viewport.applyPendingFit(() => content);
    viewport.panBy(50, 0);
    viewport.contentChanged();
    viewport.applyPendingFit(() => content);
    expect(viewport.transform.toScreen(5, 2.5)[0]).toBeCloseTo(450);
    viewport.requestFit();
    viewport.applyPendingFit(() => content);
    expect(viewport.transform.toScreen(5, 2.5)[0]).toBeCloseTo(400);
  });

  it('refits for new content while the user has not moved the view', () => {
    const viewport = sized();
    viewport.applyPendingFit(() => content);
    viewport.contentChanged();
    viewport.applyPendingFit(() => ({ minX: 100, minY: 100, maxX: 110, maxY: 105 }));
    expect(viewport.transform.toScreen(105, 102.5)[0]).toBeCloseTo(400);
  });

  it('keeps the centre of the view when the canvas is resized', () => {
    const viewport = sized();
    viewport.applyPendingFit(() => content);
    const centre = viewport.transform.toWorld(400, 300);
    viewport.resize(1000, 500);
    const [sx, sy] = viewport.transform.toScreen(centre[0], centre[1]);
    expect(sx).toBeCloseTo(500);
    expect(sy).toBeCloseTo(250);
  });

  it('zooms about the centre and centres on a point', () => {
    const viewport = sized();
    const centre = viewport.transform.toWorld(400, 300);
    viewport.zoomAtCentre(2);
    const [sx, sy] = viewport.transform.toScreen(centre[0], centre[1]);
    expect(sx).toBeCloseTo(400);
    expect(sy).toBeCloseTo(300);
    viewport.centerOn(-3, 7);
    expect(viewport.transform.toScreen(-3, 7)).toEqual([400, 300]);
  });

  it('shows a point only inside a laid-out canvas', () => {
    expect(new Viewport().shows(0, 0)).toBe(false);
    const viewport = sized();
    viewport.centerOn(0, 0);
    expect(viewport.shows(0, 0)).toBe(true);
    expect(viewport.shows(1000, 0)).toBe(false);
  });
});
