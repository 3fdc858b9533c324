// The keep-out zone being drawn (polygon_tool.ts): its edges, a dashed rubber band to the pointer
// and back to the first vertex, the vertices (the first one ringed once a click there closes it),
// in amber, or red while the shape would not be simple; filled while the server has it.

import type { PolygonDraft } from '../../polygon_tool';
import type { MapFrame, MapLayer } from '../layer';
import { tracePolygon } from '../shapes';
import { ZONE_COLOR } from './keepout_zones';

const BAD_COLOR = '#f87171';
const SUBMITTING_FILL = 'rgba(245, 158, 11, 0.25)';

export class PolygonDraftLayer implements MapLayer {
  readonly id = 'polygonDraft';
  private draft: PolygonDraft | null = null;

  /** The draft to show (the zones panel owns it). */
  attach(draft: PolygonDraft | null): void {
    this.draft = draft;
  }

  draw({ ctx, view }: MapFrame): void {
    const draft = this.draft;
    if (!draft || draft.state === 'idle') return;
    const vertices = draft.vertices;
    const color = draft.problem && vertices.length >= 3 ? BAD_COLOR : ZONE_COLOR;
    if (draft.state === 'submitting' && vertices.length >= 3) {
      tracePolygon(ctx, view, vertices);
      ctx.fillStyle = SUBMITTING_FILL;
      ctx.fill();
    }
    ctx.strokeStyle = color;
    ctx.lineWidth = 2;
    ctx.beginPath();
    vertices.forEach(([x, y], i) => (i === 0 ? ctx.moveTo(view.toScreenX(x), view.toScreenY(y)) : ctx.lineTo(view.toScreenX(x), view.toScreenY(y))));
    ctx.stroke();
    const cursor = draft.cursor;
    const last = vertices[vertices.length - 1];
    const first = vertices[0];
    if (draft.state === 'drawing' && cursor && last && first) {
      ctx.setLineDash([5, 4]);
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      ctx.moveTo(view.toScreenX(last[0]), view.toScreenY(last[1]));
      ctx.lineTo(view.toScreenX(cursor[0]), view.toScreenY(cursor[1]));
      if (vertices.length >= 2) ctx.lineTo(view.toScreenX(first[0]), view.toScreenY(first[1]));
      ctx.stroke();
      ctx.setLineDash([]);
    } else if (draft.state === 'submitting' && first && last) {
      ctx.beginPath();
      ctx.moveTo(view.toScreenX(last[0]), view.toScreenY(last[1]));
      ctx.lineTo(view.toScreenX(first[0]), view.toScreenY(first[1]));
      ctx.stroke();
    }
    ctx.fillStyle = color;
    for (const [x, y] of vertices) {
      ctx.beginPath();
      ctx.arc(view.toScreenX(x), view.toScreenY(y), 3.5, 0, 2 * Math.PI);
      ctx.fill();
    }
    if (first && vertices.length >= 3 && draft.state === 'drawing') {
      ctx.beginPath();
      ctx.arc(view.toScreenX(first[0]), view.toScreenY(first[1]), 8, 0, 2 * Math.PI);
      ctx.stroke();
    }
  }
}
