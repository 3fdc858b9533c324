// Keep-out zones of the active map: each polygon hatched in amber with its outline and, when there
// is room, its name. Not drawn over a map being built (tiles): they belong to the stored map. The
// zones drawn are published as the canvas's data-zones.

import type { MapFrame, MapLayer, Redraw } from '../layer';
import { hatchCurrentPath, tracePolygon } from '../shapes';

export interface ZoneShape {
  id: number;
  name: string;
  polygon: [number, number][];
}

export const ZONE_COLOR = '#f59e0b';
const ZONE_FILL = 'rgba(245, 158, 11, 0.10)';
const HATCH = 'rgba(245, 158, 11, 0.55)';
const LABEL = '#fde68a';
/** A zone narrower than this on screen gets no label. */
const LABEL_MIN_PX = 40;

export class KeepoutZonesLayer implements MapLayer {
  readonly id = 'zones';
  readonly toggle = 'zones';
  /** Zones in the last frame drawn. */
  drawn = 0;
  private zones: ZoneShape[] = [];

  constructor(private readonly redraw: Redraw) {}

  set(zones: ZoneShape[]): void {
    this.zones = zones;
    this.redraw();
  }

  get count(): number {
    return this.zones.length;
  }

  draw({ ctx, view, canvas, scene }: MapFrame): void {
    let drawn = 0;
    for (const zone of scene.tiles.size > 0 ? [] : this.zones) {
      if (zone.polygon.length < 3) continue;
      const xs = zone.polygon.map(([x]) => view.toScreenX(x));
      const ys = zone.polygon.map(([, y]) => view.toScreenY(y));
      const box = { minX: Math.min(...xs), minY: Math.min(...ys), maxX: Math.max(...xs), maxY: Math.max(...ys) };
      tracePolygon(ctx, view, zone.polygon);
      ctx.fillStyle = ZONE_FILL;
      ctx.fill();
      hatchCurrentPath(ctx, box, HATCH);
      tracePolygon(ctx, view, zone.polygon);
      ctx.strokeStyle = ZONE_COLOR;
      ctx.lineWidth = 2;
      ctx.stroke();
      if (zone.name && box.maxX - box.minX >= LABEL_MIN_PX) {
        ctx.font = '600 11px system-ui, sans-serif';
        ctx.fillStyle = LABEL;
        ctx.textAlign = 'center';
        ctx.fillText(zone.name, (box.minX + box.maxX) / 2, (box.minY + box.maxY) / 2 + 4);
        ctx.textAlign = 'start';
      }
      drawn++;
    }
    this.drawn = drawn;
    const text = String(drawn);
    if (canvas.dataset.zones !== text) canvas.dataset.zones = text;
  }
}
