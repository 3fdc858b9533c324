// The latest laser scan: faint rays from the sensor to each end point, and the end points as
// squares. Counts the scans it has drawn (window.__mobot.scansDrawn).

import { scanEndpoints } from '../../frames';
import type { LaserScan } from '../../frames';
import type { MapFrame, MapLayer, Redraw } from '../layer';

const RAY_COLOR = 'rgba(248, 113, 113, 0.10)';
const POINT_COLOR = '#f87171';

export class ScanLayer implements MapLayer {
  readonly id = 'scan';
  readonly toggle = 'scan';
  /** Distinct scans drawn so far (a scan redrawn for a pan counts once). */
  scansDrawn = 0;
  private scan: LaserScan | null = null;
  private scanIsNew = false;
  /** End points of the scan, reused between frames to spare the allocation. */
  private endpoints: Float32Array = new Float32Array(0);

  constructor(private readonly redraw: Redraw) {}

  set(scan: LaserScan): void {
    this.scan = scan;
    this.scanIsNew = true;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    const scan = this.scan;
    if (!scan) return;
    const { points, count } = scanEndpoints(scan, this.endpoints);
    this.endpoints = points;
    const [ox, oy] = view.toScreen(scan.sensorPose.x, scan.sensorPose.y);
    ctx.strokeStyle = RAY_COLOR;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let i = 0; i < count; i++) {
      ctx.moveTo(ox, oy);
      ctx.lineTo(view.toScreenX(points[2 * i]!), view.toScreenY(points[2 * i + 1]!));
    }
    ctx.stroke();
    const size = Math.max(2, Math.min(4, view.scale * 0.04));
    ctx.fillStyle = POINT_COLOR;
    ctx.beginPath();
    for (let i = 0; i < count; i++) {
      ctx.rect(view.toScreenX(points[2 * i]!) - size / 2, view.toScreenY(points[2 * i + 1]!) - size / 2, size, size);
    }
    ctx.fill();
    if (this.scanIsNew) {
      this.scanIsNew = false;
      this.scansDrawn++;
    }
  }
}
