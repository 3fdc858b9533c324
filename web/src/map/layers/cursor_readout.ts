// The map position under the pointer, bottom-right.

import { TEXT } from '../colors';
import type { MapFrame, MapLayer } from '../layer';

const BOX_COLOR = 'rgba(11, 15, 20, 0.7)';

export class CursorReadoutLayer implements MapLayer {
  readonly id = 'cursorReadout';

  draw({ ctx, width, height, scene }: MapFrame): void {
    const cursor = scene.pointer.cursor;
    if (!cursor) return;
    const text = `x ${cursor[0].toFixed(2)}  y ${cursor[1].toFixed(2)}`;
    ctx.font = '11px ui-monospace, monospace';
    const w = ctx.measureText(text).width;
    ctx.fillStyle = BOX_COLOR;
    ctx.fillRect(width - w - 18, height - 24, w + 12, 18);
    ctx.fillStyle = TEXT;
    ctx.fillText(text, width - w - 12, height - 11);
  }
}
