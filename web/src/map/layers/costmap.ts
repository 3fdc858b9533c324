// A costmap over the map: the global one (`costmap`, under everything but the map) or the local
// rolling window around the robot (`local_costmap`, over it), in the colours of costmap.ts (the
// legend's): faint free, a yellow-to-orange inflated gradient, magenta inscribed, red lethal, grey
// unknown. Repainted into the same offscreen image when a new costmap arrives. The cells drawn are
// published as the canvas's data-costmap-cells / data-local-costmap-cells.

import { paintCosts } from '../../costmap';
import type { Costmap } from '../../costmap';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawGridImage, PixelCanvas } from '../shapes';

export class CostmapLayer implements MapLayer {
  /** Cells of the costmap set (0 without one). */
  cells = 0;
  private costmap: Costmap | null = null;
  private painted: Costmap | null = null;
  private readonly image = new PixelCanvas();

  constructor(
    readonly id: 'costmap' | 'localCostmap',
    private readonly redraw: Redraw,
  ) {}

  get toggle(): 'costmap' | 'localCostmap' {
    return this.id;
  }

  /** The costmap to draw, or null for none. */
  set(costmap: Costmap | null): void {
    this.costmap = costmap;
    this.cells = costmap ? costmap.width * costmap.height : 0;
    this.redraw();
  }

  get current(): Costmap | null {
    return this.costmap;
  }

  draw({ ctx, view, dpr, canvas }: MapFrame): void {
    const key = this.id === 'costmap' ? 'costmapCells' : 'localCostmapCells';
    const costmap = this.costmap;
    const drawn = String(costmap ? this.cells : 0);
    if (canvas.dataset[key] !== drawn) canvas.dataset[key] = drawn;
    if (!costmap) return;
    if (this.painted !== costmap) {
      this.painted = costmap;
      if (!this.image.paint(costmap.width, costmap.height, (pixels) => paintCosts(costmap, pixels))) return;
    }
    if (this.image.canvas) drawGridImage(ctx, view, dpr, this.image.canvas, costmap.origin, costmap.resolution);
  }
}
