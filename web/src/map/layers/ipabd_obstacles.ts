// The IPaBD obstacle map of a 3D sweep over the map ("3D obstacles"): occupied cells as
// translucent squares. Pre-painted at a few pixels per cell so the squares keep a visible border.
// The number of cells drawn is published as the canvas's data-ipabd-cells (the browser test).

import { countObstacleCells, obstacleCellPixels, paintObstacleCells } from '../../ipabd';
import type { ObstacleGrid } from '../../ipabd';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawGridImage, paintedCanvas } from '../shapes';

interface PaintedGrid {
  grid: ObstacleGrid;
  image: HTMLCanvasElement;
  pixelsPerCell: number;
}

export class IpabdObstaclesLayer implements MapLayer {
  readonly id = 'ipabd';
  /** Occupied cells of the grid set (0 without one), known before it is drawn. */
  cells = 0;
  private painted: PaintedGrid | null = null;

  constructor(private readonly redraw: Redraw) {}

  /** The sweep's obstacle map to draw, or null to draw none. */
  set(grid: ObstacleGrid | null): void {
    this.cells = grid ? countObstacleCells(grid) : 0;
    this.painted = grid ? paint(grid) : null;
    this.redraw();
  }

  draw({ ctx, view, dpr, canvas }: MapFrame): void {
    const drawn = String(this.painted ? this.cells : 0);
    if (canvas.dataset.ipabdCells !== drawn) canvas.dataset.ipabdCells = drawn;
    const painted = this.painted;
    if (!painted) return;
    const { grid, image, pixelsPerCell } = painted;
    drawGridImage(ctx, view, dpr, image, grid.origin, grid.resolution / pixelsPerCell);
  }
}

function paint(grid: ObstacleGrid): PaintedGrid | null {
  if (grid.width <= 0 || grid.height <= 0) return null;
  const k = obstacleCellPixels(grid.width, grid.height);
  const image = paintedCanvas(grid.width * k, grid.height * k, (pixels) => paintObstacleCells(grid, pixels, k));
  return image ? { grid, image, pixelsPerCell: k } : null;
}
