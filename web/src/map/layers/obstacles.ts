// Obstacles dropped into the simulation from this page: orange discs of their radius, numbered
// once they are large enough on screen for the id to fit.

import type { MapFrame, MapLayer, Redraw } from '../layer';

export interface ObstacleMarker {
  id: number;
  x: number;
  y: number;
  radius: number;
}

const FILL = 'rgba(251, 146, 60, 0.35)';
const STROKE = '#fb923c';
const LABEL_COLOR = '#fff7ed';
/** Smallest disc (px) drawn, and the radius above which the id is written in it. */
const MIN_RADIUS_PX = 2;
const LABEL_MIN_RADIUS_PX = 8;

export class ObstaclesLayer implements MapLayer {
  readonly id = 'obstacles';
  private obstacles: ObstacleMarker[] = [];

  constructor(private readonly redraw: Redraw) {}

  set(obstacles: ObstacleMarker[]): void {
    this.obstacles = obstacles;
    this.redraw();
  }

  draw(frame: MapFrame): void {
    for (const obstacle of this.obstacles) drawObstacle(frame, obstacle);
  }
}

function drawObstacle({ ctx, view }: MapFrame, o: ObstacleMarker): void {
  const [sx, sy] = view.toScreen(o.x, o.y);
  const r = Math.max(MIN_RADIUS_PX, o.radius * view.scale);
  ctx.beginPath();
  ctx.arc(sx, sy, r, 0, 2 * Math.PI);
  ctx.fillStyle = FILL;
  ctx.fill();
  ctx.strokeStyle = STROKE;
  ctx.lineWidth = 2;
  ctx.stroke();
  if (r > LABEL_MIN_RADIUS_PX) {
    ctx.fillStyle = LABEL_COLOR;
    ctx.font = '600 10px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.fillText(String(o.id), sx, sy);
    ctx.textAlign = 'start';
    ctx.textBaseline = 'alphabetic';
  }
}
