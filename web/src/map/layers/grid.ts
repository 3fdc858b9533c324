// A metre grid behind everything while there is no whole map (none yet, or one being built from
// tiles), so pan and zoom still show something.

import type { MapFrame, MapLayer } from '../layer';

const GRID_COLOR = 'rgba(148, 163, 184, 0.08)';
/** Grid lines are at least this far apart on screen (the step grows 1, 5, 25 ... m). */
const MIN_SPACING_PX = 24;

export class GridLayer implements MapLayer {
  readonly id = 'grid';

  draw({ ctx, view, width, height, scene }: MapFrame): void {
    if (scene.map && scene.tiles.size === 0) return;
    let step = 1;
    while (step * view.scale < MIN_SPACING_PX) step *= 5;
    const [x0, y1] = view.toWorld(0, 0);
    const [x1, y0] = view.toWorld(width, height);
    ctx.strokeStyle = GRID_COLOR;
    ctx.lineWidth = 1;
    ctx.beginPath();
    // Rounded to the pixel centre (+0.5) so 1 px lines are not smeared over two pixels.
    for (let x = Math.floor(x0 / step) * step; x <= x1; x += step) {
      const sx = Math.round(view.toScreenX(x)) + 0.5;
      ctx.moveTo(sx, 0);
      ctx.lineTo(sx, height);
    }
    for (let y = Math.floor(y0 / step) * step; y <= y1; y += step) {
      const sy = Math.round(view.toScreenY(y)) + 0.5;
      ctx.moveTo(0, sy);
      ctx.lineTo(width, sy);
    }
    ctx.stroke();
  }
}
