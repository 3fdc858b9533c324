// Canvas view of the map frame: occupancy grid, robot footprint + heading, trail, laser scan,
// sonar cones, simulator ground truth and an optional trajectory overlay. Pan by dragging, zoom
// with the wheel about the cursor. Redraws at most once per animation frame and only when
// something changed, always with the latest data.

import { mapCorners, scanEndpoints, UNKNOWN_CELL } from './frames';
import type { LaserScan, MapGrid, Pose2D } from './frames';
import { boundsOf, ViewTransform, wheelZoomFactor } from './view';
import type { Bounds } from './view';

export interface SonarReading {
  x: number;
  y: number;
  theta: number;
  cone: number;
  range: number;
  range_min: number;
  range_max: number;
}

export const FOOTPRINT_M = 0.6;

const COLORS = {
  background: '#0b0f14',
  grid: 'rgba(148, 163, 184, 0.08)',
  free: [46, 53, 64],
  occupied: [214, 221, 231],
  unknown: [20, 27, 45],
  scanRay: 'rgba(248, 113, 113, 0.10)',
  scanPoint: '#f87171',
  sonarFill: 'rgba(56, 189, 248, 0.10)',
  sonarEcho: 'rgba(56, 189, 248, 0.55)',
  robotFill: 'rgba(56, 189, 248, 0.22)',
  robotStroke: '#38bdf8',
  heading: '#f8fafc',
  trail: 'rgba(250, 204, 21, 0.75)',
  truth: '#c4b5fd',
  trajectory: '#34d399',
  text: 'rgba(226, 232, 240, 0.85)',
};

/** 256-entry RGBA lookup (as little-endian u32) from cell value to colour. */
function buildPalette(): Uint32Array {
  const lut = new Uint32Array(256);
  const pack = (r: number, g: number, b: number, a = 255) => ((a << 24) | (b << 16) | (g << 8) | r) >>> 0;
  for (let v = 0; v < 256; v++) {
    if (v > 100) {
      lut[v] = pack(COLORS.unknown[0]!, COLORS.unknown[1]!, COLORS.unknown[2]!);
      continue;
    }
    const k = v / 100;
    const c = COLORS.free.map((f, i) => Math.round(f + (COLORS.occupied[i]! - f) * k));
    lut[v] = pack(c[0]!, c[1]!, c[2]!);
  }
  return lut;
}

const PALETTE = buildPalette();

/** Paints a grid into RGBA pixels, image row r = grid row r (flipped by the view transform). */
export function paintGrid(map: MapGrid, pixels: Uint32Array): void {
  const n = map.width * map.height;
  for (let i = 0; i < n; i++) pixels[i] = PALETTE[map.cells[i] ?? UNKNOWN_CELL]!;
}

export class MapView {
  readonly view = new ViewTransform();
  scansDrawn = 0;
  framesDrawn = 0;
  mapShown = false;
  /** Poses kept in the trail. */
  readonly trailLength = 600;
  readonly layers = { scan: true, sonar: true, trail: true, truth: true };

  private readonly ctx: CanvasRenderingContext2D;
  private map: MapGrid | null = null;
  private mapImage: HTMLCanvasElement | null = null;
  private pose: Pose2D | null = null;
  private truth: Pose2D | null = null;
  private scan: LaserScan | null = null;
  private scanIsNew = false;
  private scanPoints: Float32Array = new Float32Array(0);
  private sonar: SonarReading[] = [];
  private trail: Float64Array;
  private trailStart = 0;
  private trailCount = 0;
  private overlay: Float64Array | null = null;
  private dirty = true;
  private needsFit = true;
  private userMoved = false;
  private frame = 0;
  private cursor: [number, number] | null = null;
  private dpr = 1;
  private cssWidth = 0;
  private cssHeight = 0;
  private drag: { id: number; x: number; y: number } | null = null;
  private readonly resizeObserver: ResizeObserver;

  constructor(
    readonly canvas: HTMLCanvasElement,
    private readonly options: { showRobot?: boolean } = {},
  ) {
    const ctx = canvas.getContext('2d', { alpha: false });
    if (!ctx) throw new Error('canvas 2D is not available');
    this.ctx = ctx;
    this.trail = new Float64Array(this.trailLength * 2);
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(canvas);
    this.attachInput();
    this.resize();
    this.loop();
  }

  destroy(): void {
    cancelAnimationFrame(this.frame);
    this.resizeObserver.disconnect();
  }

  // ---- data ----

  setMap(map: MapGrid): void {
    const previous = this.map;
    this.map = map;
    this.mapImage = document.createElement('canvas');
    this.mapImage.width = Math.max(1, map.width);
    this.mapImage.height = Math.max(1, map.height);
    const ctx = this.mapImage.getContext('2d');
    if (ctx && map.width > 0 && map.height > 0) {
      const image = ctx.createImageData(map.width, map.height);
      paintGrid(map, new Uint32Array(image.data.buffer));
      ctx.putImageData(image, 0, 0);
    }
    const changedShape =
      !previous ||
      previous.id !== map.id ||
      previous.width !== map.width ||
      previous.height !== map.height ||
      previous.resolution !== map.resolution;
    if (changedShape && !this.userMoved) this.needsFit = true;
    this.mapShown = true;
    this.dirty = true;
  }

  getMap(): MapGrid | null {
    return this.map;
  }

  setPose(pose: Pose2D): void {
    this.pose = pose;
    const last = this.trailCount > 0 ? (this.trailStart + this.trailCount - 1) % this.trailLength : -1;
    if (last < 0 || Math.hypot(this.trail[2 * last]! - pose.x, this.trail[2 * last + 1]! - pose.y) > 0.02) {
      let slot: number;
      if (this.trailCount < this.trailLength) {
        slot = (this.trailStart + this.trailCount) % this.trailLength;
        this.trailCount++;
      } else {
        slot = this.trailStart;
        this.trailStart = (this.trailStart + 1) % this.trailLength;
      }
      this.trail[2 * slot] = pose.x;
      this.trail[2 * slot + 1] = pose.y;
    }
    this.dirty = true;
  }

  clearTrail(): void {
    this.trailCount = 0;
    this.trailStart = 0;
    this.dirty = true;
  }

  setTruth(pose: Pose2D | null): void {
    this.truth = pose;
    this.dirty = true;
  }

  setScan(scan: LaserScan): void {
    this.scan = scan;
    this.scanIsNew = true;
    this.dirty = true;
  }

  setSonar(readings: SonarReading[]): void {
    this.sonar = readings;
    this.dirty = true;
  }

  /** A trajectory to draw over the map ([x, y] pairs), or null. */
  setOverlay(points: { x: number; y: number }[] | null, fit = false): void {
    if (!points) {
      this.overlay = null;
    } else {
      this.overlay = new Float64Array(points.length * 2);
      points.forEach((p, i) => {
        this.overlay![2 * i] = p.x;
        this.overlay![2 * i + 1] = p.y;
      });
      if (fit && points.length > 1) {
        const b = boundsOf(points.map((p) => [p.x, p.y] as [number, number]));
        if (b) this.fitBounds(grow(b, 1.0));
      }
    }
    this.dirty = true;
  }

  /** Whether the robot's pose is inside the visible canvas (for the browser test). */
  robotVisible(): boolean {
    if (!this.pose || this.cssWidth < 2) return false;
    const [sx, sy] = this.view.toScreen(this.pose.x, this.pose.y);
    return sx >= 0 && sy >= 0 && sx <= this.cssWidth && sy <= this.cssHeight;
  }

  /** Asks for a redraw (after changing layers). */
  invalidate(): void {
    this.dirty = true;
  }

  // ---- view ----

  /** Fits the map (or, without one, the robot's surroundings) into the canvas. */
  fit(): void {
    this.userMoved = false;
    this.needsFit = true;
    this.dirty = true;
  }

  centerOnRobot(): void {
    if (!this.pose) return;
    this.view.originX = this.cssWidth / 2 - this.pose.x * this.view.scale;
    this.view.originY = this.cssHeight / 2 + this.pose.y * this.view.scale;
    this.userMoved = true;
    this.dirty = true;
  }

  zoom(factor: number): void {
    this.view.zoomAbout(this.cssWidth / 2, this.cssHeight / 2, factor);
    this.userMoved = true;
    this.dirty = true;
  }

  private fitBounds(bounds: Bounds): void {
    if (this.cssWidth < 2 || this.cssHeight < 2) return;
    this.view.fit(bounds, this.cssWidth, this.cssHeight, 24);
    this.dirty = true;
  }

  private applyPendingFit(): void {
    if (!this.needsFit || this.cssWidth < 2 || this.cssHeight < 2) return;
    let bounds: Bounds | null = null;
    if (this.map) bounds = boundsOf(mapCorners(this.map));
    else if (this.pose) bounds = grow({ minX: this.pose.x, minY: this.pose.y, maxX: this.pose.x, maxY: this.pose.y }, 5);
    if (!bounds) return;
    this.view.fit(bounds, this.cssWidth, this.cssHeight, 24);
    this.needsFit = false;
  }

  private resize(): void {
    const rect = this.canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const width = Math.round(rect.width);
    const height = Math.round(rect.height);
    // A hidden page (display: none) has no size: keep the view as it was until it is shown again.
    if (width < 2 || height < 2) return;
    if (width === this.cssWidth && height === this.cssHeight && dpr === this.dpr) return;
    // Keep the centre of the view where it was.
    if (this.cssWidth > 0 && this.cssHeight > 0) {
      this.view.panBy((width - this.cssWidth) / 2, (height - this.cssHeight) / 2);
    }
    this.cssWidth = width;
    this.cssHeight = height;
    this.dpr = dpr;
    this.canvas.width = Math.max(1, Math.round(width * dpr));
    this.canvas.height = Math.max(1, Math.round(height * dpr));
    this.dirty = true;
  }

  private attachInput(): void {
    const canvas = this.canvas;
    canvas.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      this.drag = { id: e.pointerId, x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
      canvas.classList.add('dragging');
    });
    canvas.addEventListener('pointermove', (e) => {
      const rect = canvas.getBoundingClientRect();
      this.cursor = this.view.toWorld(e.clientX - rect.left, e.clientY - rect.top);
      if (this.drag && this.drag.id === e.pointerId) {
        this.view.panBy(e.clientX - this.drag.x, e.clientY - this.drag.y);
        this.drag.x = e.clientX;
        this.drag.y = e.clientY;
        this.userMoved = true;
      }
      this.dirty = true;
    });
    const endDrag = (e: PointerEvent) => {
      if (this.drag && this.drag.id === e.pointerId) {
        this.drag = null;
        canvas.classList.remove('dragging');
      }
    };
    canvas.addEventListener('pointerup', endDrag);
    canvas.addEventListener('pointercancel', endDrag);
    canvas.addEventListener('pointerleave', () => {
      this.cursor = null;
      this.dirty = true;
    });
    canvas.addEventListener(
      'wheel',
      (e) => {
        e.preventDefault();
        const rect = canvas.getBoundingClientRect();
        this.view.zoomAbout(e.clientX - rect.left, e.clientY - rect.top, wheelZoomFactor(e.deltaY, e.deltaMode));
        this.userMoved = true;
        this.dirty = true;
      },
      { passive: false },
    );
    canvas.addEventListener('dblclick', () => this.fit());
  }

  // ---- drawing ----

  private loop = (): void => {
    this.frame = requestAnimationFrame(this.loop);
    this.resize();
    if (!this.dirty) return;
    this.dirty = false;
    this.draw();
  };

  /** Draws now (also used by tests through the rAF loop). */
  draw(): void {
    this.applyPendingFit();
    const ctx = this.ctx;
    const dpr = this.dpr;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = COLORS.background;
    ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);

    if (this.map && this.mapImage) this.drawMap(this.map, this.mapImage);
    else this.drawGrid();

    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    if (this.layers.sonar) this.drawSonar();
    if (this.layers.scan) this.drawScan();
    if (this.overlay) this.drawOverlay(this.overlay);
    if (this.options.showRobot !== false) {
      if (this.layers.trail) this.drawTrail();
      if (this.truth && this.layers.truth) this.drawRobot(this.truth, true);
      if (this.pose) this.drawRobot(this.pose, false);
    }
    this.drawScaleBar();
    this.drawCursor();
    this.framesDrawn++;
  }

  private drawMap(map: MapGrid, image: HTMLCanvasElement): void {
    const ctx = this.ctx;
    ctx.setTransform(...this.view.matrix(this.dpr));
    ctx.translate(map.origin.x, map.origin.y);
    ctx.rotate(map.origin.theta);
    ctx.scale(map.resolution, map.resolution);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(image, 0, 0);
    ctx.imageSmoothingEnabled = true;
  }

  private drawGrid(): void {
    const ctx = this.ctx;
    ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    const v = this.view;
    let step = 1;
    while (step * v.scale < 24) step *= 5;
    const [x0, y1] = v.toWorld(0, 0);
    const [x1, y0] = v.toWorld(this.cssWidth, this.cssHeight);
    ctx.strokeStyle = COLORS.grid;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = Math.floor(x0 / step) * step; x <= x1; x += step) {
      const sx = Math.round(v.toScreenX(x)) + 0.5;
      ctx.moveTo(sx, 0);
      ctx.lineTo(sx, this.cssHeight);
    }
    for (let y = Math.floor(y0 / step) * step; y <= y1; y += step) {
      const sy = Math.round(v.toScreenY(y)) + 0.5;
      ctx.moveTo(0, sy);
      ctx.lineTo(this.cssWidth, sy);
    }
    ctx.stroke();
  }

  private drawScan(): void {
    const scan = this.scan;
    if (!scan) return;
    const { points, count } = scanEndpoints(scan, this.scanPoints);
    this.scanPoints = points;
    const ctx = this.ctx;
    const v = this.view;
    const [ox, oy] = v.toScreen(scan.sensorPose.x, scan.sensorPose.y);
    ctx.strokeStyle = COLORS.scanRay;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let i = 0; i < count; i++) {
      ctx.moveTo(ox, oy);
      ctx.lineTo(v.toScreenX(points[2 * i]!), v.toScreenY(points[2 * i + 1]!));
    }
    ctx.stroke();
    const size = Math.max(2, Math.min(4, v.scale * 0.04));
    ctx.fillStyle = COLORS.scanPoint;
    ctx.beginPath();
    for (let i = 0; i < count; i++) {
      ctx.rect(v.toScreenX(points[2 * i]!) - size / 2, v.toScreenY(points[2 * i + 1]!) - size / 2, size, size);
    }
    ctx.fill();
    if (this.scanIsNew) {
      this.scanIsNew = false;
      this.scansDrawn++;
    }
  }

  private drawSonar(): void {
    if (this.sonar.length === 0) return;
    const ctx = this.ctx;
    const v = this.view;
    for (const r of this.sonar) {
      const echo = r.range >= r.range_min && r.range < r.range_max;
      const range = Math.min(Math.max(r.range, 0), r.range_max);
      if (!(range > 0)) continue;
      const [sx, sy] = v.toScreen(r.x, r.y);
      const radius = range * v.scale;
      const half = Math.max(r.cone, 0.01) / 2;
      // Screen y points down, so angles are negated.
      ctx.beginPath();
      ctx.moveTo(sx, sy);
      ctx.arc(sx, sy, radius, -r.theta - half, -r.theta + half);
      ctx.closePath();
      ctx.fillStyle = COLORS.sonarFill;
      ctx.fill();
      if (echo) {
        ctx.beginPath();
        ctx.arc(sx, sy, radius, -r.theta - half, -r.theta + half);
        ctx.strokeStyle = COLORS.sonarEcho;
        ctx.lineWidth = 2;
        ctx.stroke();
      }
    }
  }

  private drawOverlay(xy: Float64Array): void {
    const n = xy.length / 2;
    if (n === 0) return;
    this.drawPolyline(xy, n, 0, COLORS.trajectory, 2);
    const ctx = this.ctx;
    const [sx, sy] = this.view.toScreen(xy[0]!, xy[1]!);
    const [ex, ey] = this.view.toScreen(xy[2 * n - 2]!, xy[2 * n - 1]!);
    ctx.lineWidth = 2;
    ctx.strokeStyle = COLORS.trajectory;
    ctx.fillStyle = COLORS.background;
    ctx.beginPath();
    ctx.arc(sx, sy, 5, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = COLORS.trajectory;
    ctx.beginPath();
    ctx.arc(ex, ey, 5, 0, 2 * Math.PI);
    ctx.fill();
  }

  private drawTrail(): void {
    if (this.trailCount < 2) return;
    this.drawPolyline(this.trail, this.trailCount, this.trailStart, COLORS.trail, 1.5, this.trailLength);
  }

  private drawPolyline(
    xy: Float64Array,
    count: number,
    start: number,
    color: string,
    width: number,
    ring = count,
  ): void {
    if (count < 2) return;
    const ctx = this.ctx;
    const v = this.view;
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.lineJoin = 'round';
    ctx.beginPath();
    for (let k = 0; k < count; k++) {
      const i = (start + k) % ring;
      const sx = v.toScreenX(xy[2 * i]!);
      const sy = v.toScreenY(xy[2 * i + 1]!);
      if (k === 0) ctx.moveTo(sx, sy);
      else ctx.lineTo(sx, sy);
    }
    ctx.stroke();
  }

  private drawRobot(pose: Pose2D, ghost: boolean): void {
    const ctx = this.ctx;
    const v = this.view;
    const half = FOOTPRINT_M / 2;
    const c = Math.cos(pose.theta);
    const s = Math.sin(pose.theta);
    const corner = (lx: number, ly: number): [number, number] =>
      v.toScreen(pose.x + c * lx - s * ly, pose.y + s * lx + c * ly);
    const corners = [corner(half, half), corner(-half, half), corner(-half, -half), corner(half, -half)];
    ctx.beginPath();
    corners.forEach(([x, y], i) => (i === 0 ? ctx.moveTo(x, y) : ctx.lineTo(x, y)));
    ctx.closePath();
    if (ghost) {
      ctx.setLineDash([5, 4]);
      ctx.strokeStyle = COLORS.truth;
      ctx.lineWidth = 1.5;
      ctx.stroke();
      ctx.setLineDash([]);
    } else {
      ctx.fillStyle = COLORS.robotFill;
      ctx.fill();
      ctx.strokeStyle = COLORS.robotStroke;
      ctx.lineWidth = 2;
      ctx.stroke();
    }
    // Heading: a line from the centre to the front edge and an arrow head.
    const [cx, cy] = v.toScreen(pose.x, pose.y);
    const [fx, fy] = corner(half * 1.5, 0);
    const [l, r] = [corner(half * 1.05, half * 0.35), corner(half * 1.05, -half * 0.35)];
    ctx.beginPath();
    ctx.moveTo(cx, cy);
    ctx.lineTo(fx, fy);
    ctx.moveTo(l[0], l[1]);
    ctx.lineTo(fx, fy);
    ctx.lineTo(r[0], r[1]);
    ctx.strokeStyle = ghost ? COLORS.truth : COLORS.heading;
    ctx.lineWidth = ghost ? 1.5 : 2;
    ctx.stroke();
  }

  private drawScaleBar(): void {
    const ctx = this.ctx;
    const target = 100 / this.view.scale; // metres in ~100 px
    const magnitude = 10 ** Math.floor(Math.log10(target));
    const step = [1, 2, 5, 10].map((k) => k * magnitude).find((m) => m >= target * 0.6) ?? magnitude;
    const px = step * this.view.scale;
    const x = 14;
    const y = this.cssHeight - 14;
    ctx.strokeStyle = COLORS.text;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(x, y - 5);
    ctx.lineTo(x, y);
    ctx.lineTo(x + px, y);
    ctx.lineTo(x + px, y - 5);
    ctx.stroke();
    ctx.fillStyle = COLORS.text;
    ctx.font = '11px system-ui, sans-serif';
    ctx.fillText(step >= 1 ? `${step} m` : `${Math.round(step * 100)} cm`, x + 4, y - 6);
  }

  private drawCursor(): void {
    if (!this.cursor) return;
    const ctx = this.ctx;
    const text = `x ${this.cursor[0].toFixed(2)}  y ${this.cursor[1].toFixed(2)}`;
    ctx.font = '11px ui-monospace, monospace';
    const w = ctx.measureText(text).width;
    ctx.fillStyle = 'rgba(11, 15, 20, 0.7)';
    ctx.fillRect(this.cssWidth - w - 18, this.cssHeight - 24, w + 12, 18);
    ctx.fillStyle = COLORS.text;
    ctx.fillText(text, this.cssWidth - w - 12, this.cssHeight - 11);
  }
}

function grow(b: Bounds, margin: number): Bounds {
  return { minX: b.minX - margin, minY: b.minY - margin, maxX: b.maxX + margin, maxY: b.maxY + margin };
}
