// A scale bar in the bottom-left corner: a round length (1, 2, 5 x 10^k m) about 100 px long.

import { TEXT } from '../colors';
import type { MapFrame, MapLayer } from '../layer';

const TARGET_PX = 100;
const INSET_PX = 14;

export class ScaleBarLayer implements MapLayer {
  readonly id = 'scaleBar';

  draw({ ctx, view, height }: MapFrame): void {
    const metres = roundLength(TARGET_PX / view.scale);
    const px = metres * view.scale;
    const x = INSET_PX;
    const y = height - INSET_PX;
    ctx.strokeStyle = TEXT;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(x, y - 5);
    ctx.lineTo(x, y);
    ctx.lineTo(x + px, y);
    ctx.lineTo(x + px, y - 5);
    ctx.stroke();
    ctx.fillStyle = TEXT;
    ctx.font = '11px system-ui, sans-serif';
    ctx.fillText(metres >= 1 ? `${metres} m` : `${Math.round(metres * 100)} cm`, x + 4, y - 6);
  }
}

/** The first of 1, 2, 5, 10 x 10^k that is at least 0.6 x `target` metres. */
function roundLength(target: number): number {
  const magnitude = 10 ** Math.floor(Math.log10(target));
  return [1, 2, 5, 10].map((k) => k * magnitude).find((m) => m >= target * 0.6) ?? magnitude;
}
