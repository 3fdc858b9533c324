// Canvas view of the map frame: occupancy grid, robot footprint + heading, trail, laser scan,
// sonar cones, simulator ground truth and an optional trajectory overlay. Pan by dragging, zoom
// with the wheel about the cursor. Redraws at most once per animation frame and only when
// something changed, always with the latest data.

import { mapCorners, scanEndpoints, UNKNOWN_CELL } from './frames';
import type { LaserScan, MapGrid, Pose2D } from './frames';
import { covarianceEllipse, dragHeading, headingSigma } from './goals';
import type { GoalStatus } from './goals';
import { countObstacleCells, obstacleCellPixels, paintObstacleCells } from './ipabd';
import type { ObstacleGrid } from './ipabd';
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

/** Sigmas of the drawn uncertainty (covariance ellipse and heading wedge). */
export const UNCERTAINTY_SIGMAS = 2;

/** The goal marker: target and, when given, the requested heading. */
export interface GoalMarker {
  x: number;
  y: number;
  theta?: number;
  status: GoalStatus;
}

export interface ObstacleMarker {
  id: number;
  x: number;
  y: number;
  radius: number;
}

/**
 * A press-and-drag tool on the map (set goal, set pose, drop obstacle). While a tool is active a
 * left press belongs to it instead of panning; `done` gets the press point and, when the pointer
 * was dragged, the heading of the drag (map frame).
 */
export interface MapTool {
  name: string;
  color: string;
  /** Whether a drag sets a heading (arrow preview). */
  heading: boolean;
  /** A circle of this radius (m) is previewed at the press point (obstacles). */
  radius?: number;
  done(point: { x: number; y: number }, heading: number | null): void;
}

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
  covFill: 'rgba(56, 189, 248, 0.16)',
  covStroke: 'rgba(125, 211, 252, 0.95)',
  wedgeFill: 'rgba(250, 204, 21, 0.22)',
  wedgeStroke: 'rgba(250, 204, 21, 0.8)',
  path: '#34d399',
  pathDone: 'rgba(52, 211, 153, 0.35)',
  obstacleFill: 'rgba(251, 146, 60, 0.35)',
  obstacleStroke: '#fb923c',
  error: '#f87171',
};

/** Colour of a goal status (marker, badges). */
export const STATUS_COLORS: Record<GoalStatus, string> = {
  planning: '#fbbf24',
  active: '#38bdf8',
  succeeded: '#34d399',
  failed: '#f87171',
  canceled: '#94a3b8',
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
  readonly layers = { scan: true, sonar: true, trail: true, truth: true, cov: true, path: true };

  private readonly ctx: CanvasRenderingContext2D;
  private map: MapGrid | null = null;
  private mapImage: HTMLCanvasElement | null = null;
  /** IPaBD obstacle map of a 3D sweep, pre-painted (occupied cells only) at `obstaclePixels` px per cell. */
  private obstacleGrid: ObstacleGrid | null = null;
  private obstacleImage: HTMLCanvasElement | null = null;
  private obstaclePixels = 1;
  /** Occupied IPaBD cells in the overlay (0 without one); also on the canvas as data-ipabd-cells once drawn. */
  obstacleCells = 0;
  private pose: Pose2D | null = null;
  private cov: readonly number[] | null = null;
  private path: Float64Array = new Float64Array(0);
  private pathDone = false;
  private goal: GoalMarker | null = null;
  private obstacles: ObstacleMarker[] = [];
  private errorMark: { x: number; y: number; until: number } | null = null;
  private tool: MapTool | null = null;
  private press: { id: number; x: number; y: number; cx: number; cy: number } | null = null;
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

  /** The 3D sweep's IPaBD obstacle map to draw over the map as translucent squares, or null. */
  setObstacleGrid(grid: ObstacleGrid | null): void {
    this.obstacleGrid = grid;
    this.obstacleImage = null;
    this.obstacleCells = grid ? countObstacleCells(grid) : 0;
    if (grid && grid.width > 0 && grid.height > 0) {
      const k = obstacleCellPixels(grid.width, grid.height);
      const image = document.createElement('canvas');
      image.width = grid.width * k;
      image.height = grid.height * k;
      const ctx = image.getContext('2d');
      if (ctx) {
        const data = ctx.createImageData(image.width, image.height);
        paintObstacleCells(grid, new Uint32Array(data.data.buffer), k);
        ctx.putImageData(data, 0, 0);
        this.obstacleImage = image;
        this.obstaclePixels = k;
      }
    }
    this.dirty = true;
  }

  getMap(): MapGrid | null {
    return this.map;
  }

  setPose(pose: Pose2D & { cov?: readonly number[] }): void {
    this.pose = pose;
    this.cov = Array.isArray(pose.cov) && pose.cov.length === 9 ? pose.cov : null;
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

  /** The current plan ([x, y] pairs); `done` draws it faded (the goal has ended). */
  setPath(points: readonly (readonly [number, number])[], done = false): void {
    const xy = new Float64Array(points.length * 2);
    points.forEach((p, i) => {
      xy[2 * i] = p[0];
      xy[2 * i + 1] = p[1];
    });
    this.path = xy;
    this.pathDone = done;
    this.dirty = true;
  }

  get pathPoints(): number {
    return this.path.length / 2;
  }

  setGoal(goal: GoalMarker | null): void {
    this.goal = goal;
    this.dirty = true;
  }

  setObstacles(obstacles: ObstacleMarker[]): void {
    this.obstacles = obstacles;
    this.dirty = true;
  }

  /** Marks a refused map point (e.g. a goal in a wall) for a few seconds. */
  flashError(x: number, y: number, ms = 4000): void {
    this.errorMark = { x, y, until: performance.now() + ms };
    this.dirty = true;
    window.setTimeout(() => (this.dirty = true), ms + 20);
  }

  /** Activates a press-and-drag tool (null: back to panning). */
  setTool(tool: MapTool | null): void {
    this.tool = tool;
    if (this.press) {
      try {
        this.canvas.releasePointerCapture(this.press.id);
      } catch {
        // not captured
      }
    }
    this.press = null;
    this.canvas.classList.toggle('tool', !!tool);
    this.dirty = true;
  }

  get activeTool(): string | null {
    return this.tool?.name ?? null;
  }

  /** Map frame -> CSS pixels relative to the viewport (for the browser test). */
  mapToClient(x: number, y: number): [number, number] {
    const rect = this.canvas.getBoundingClientRect();
    const [sx, sy] = this.view.toScreen(x, y);
    return [rect.left + sx, rect.top + sy];
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
    const worldOf = (e: PointerEvent): [number, number] => {
      const rect = canvas.getBoundingClientRect();
      return this.view.toWorld(e.clientX - rect.left, e.clientY - rect.top);
    };
    canvas.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      if (this.tool) {
        const [x, y] = worldOf(e);
        this.press = { id: e.pointerId, x, y, cx: x, cy: y };
        canvas.setPointerCapture(e.pointerId);
        this.dirty = true;
        return;
      }
      this.drag = { id: e.pointerId, x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
      canvas.classList.add('dragging');
    });
    canvas.addEventListener('pointermove', (e) => {
      const rect = canvas.getBoundingClientRect();
      this.cursor = this.view.toWorld(e.clientX - rect.left, e.clientY - rect.top);
      if (this.press && this.press.id === e.pointerId) {
        this.press.cx = this.cursor[0];
        this.press.cy = this.cursor[1];
      } else if (this.drag && this.drag.id === e.pointerId) {
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
    canvas.addEventListener('pointerup', (e) => {
      const press = this.press;
      if (press && press.id === e.pointerId && this.tool) {
        const [x, y] = worldOf(e);
        const tool = this.tool;
        this.press = null;
        this.dirty = true;
        tool.done({ x: press.x, y: press.y }, tool.heading ? dragHeading(press, { x, y }, this.view.scale) : null);
        return;
      }
      endDrag(e);
    });
    canvas.addEventListener('pointercancel', (e) => {
      if (this.press && this.press.id === e.pointerId) {
        this.press = null;
        this.dirty = true;
      }
      endDrag(e);
    });
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
    canvas.addEventListener('dblclick', () => {
      if (!this.tool) this.fit();
    });
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
    this.drawObstacleGrid();

    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    if (this.layers.sonar) this.drawSonar();
    if (this.layers.scan) this.drawScan();
    if (this.overlay) this.drawOverlay(this.overlay);
    this.drawObstacles();
    if (this.layers.path) this.drawPath();
    if (this.goal) this.drawGoal(this.goal);
    if (this.options.showRobot !== false) {
      if (this.layers.trail) this.drawTrail();
      const uncertainty = this.pose && this.cov && this.layers.cov;
      if (uncertainty) this.drawHeadingWedge(this.pose!, this.cov!);
      if (this.truth && this.layers.truth) this.drawRobot(this.truth, true);
      if (this.pose) this.drawRobot(this.pose, false);
      if (uncertainty) this.drawCovarianceEllipse(this.pose!, this.cov!);
    }
    this.drawErrorMark();
    this.drawPress();
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

  private drawObstacleGrid(): void {
    const grid = this.obstacleGrid;
    const drawn = grid && this.obstacleImage ? this.obstacleCells : 0;
    if (this.canvas.dataset.ipabdCells !== String(drawn)) this.canvas.dataset.ipabdCells = String(drawn);
    if (!grid || !this.obstacleImage) return;
    const ctx = this.ctx;
    ctx.setTransform(...this.view.matrix(this.dpr));
    ctx.translate(grid.origin.x, grid.origin.y);
    ctx.rotate(grid.origin.theta);
    ctx.scale(grid.resolution / this.obstaclePixels, grid.resolution / this.obstaclePixels);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(this.obstacleImage, 0, 0);
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

  private drawPath(): void {
    const n = this.path.length / 2;
    if (n < 2) return;
    const ctx = this.ctx;
    if (this.pathDone) {
      ctx.setLineDash([6, 5]);
      this.drawPolyline(this.path, n, 0, COLORS.pathDone, 2);
      ctx.setLineDash([]);
      return;
    }
    // A dark casing under the line keeps it readable over the map and the scan.
    this.drawPolyline(this.path, n, 0, 'rgba(11, 15, 20, 0.75)', 5);
    this.drawPolyline(this.path, n, 0, COLORS.path, 2.5);
    const v = this.view;
    ctx.fillStyle = COLORS.path;
    const r = 2.2;
    ctx.beginPath();
    for (let i = 1; i < n - 1; i++) {
      const sx = v.toScreenX(this.path[2 * i]!);
      const sy = v.toScreenY(this.path[2 * i + 1]!);
      ctx.moveTo(sx + r, sy);
      ctx.arc(sx, sy, r, 0, 2 * Math.PI);
    }
    ctx.fill();
  }

  private drawGoal(goal: GoalMarker): void {
    const ctx = this.ctx;
    const [sx, sy] = this.view.toScreen(goal.x, goal.y);
    const color = STATUS_COLORS[goal.status] ?? COLORS.path;
    const finished = goal.status === 'succeeded' || goal.status === 'failed' || goal.status === 'canceled';
    const r = Math.max(7, Math.min(14, 0.18 * this.view.scale));
    ctx.globalAlpha = finished ? 0.6 : 1;
    // A flag-like target: ring, dot and, with a heading, an arrow.
    ctx.lineWidth = 2.5;
    ctx.strokeStyle = 'rgba(11, 15, 20, 0.8)';
    ctx.beginPath();
    ctx.arc(sx, sy, r + 1.5, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.strokeStyle = color;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(sx, sy, r, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.fillStyle = color;
    ctx.beginPath();
    ctx.arc(sx, sy, 3, 0, 2 * Math.PI);
    ctx.fill();
    if (goal.theta !== undefined) this.drawArrow(sx, sy, goal.theta, r + Math.max(14, 0.45 * this.view.scale), color, 2.5);
    if (goal.status === 'failed') {
      ctx.strokeStyle = color;
      ctx.lineWidth = 2;
      this.strokeCross(sx, sy, r * 0.55);
    }
    ctx.globalAlpha = 1;
  }

  /** An arrow from (sx, sy) along the map-frame angle `theta`, `length` pixels long. */
  /** An X of half-size k screen pixels at (sx, sy), in the current stroke style. */
  private strokeCross(sx: number, sy: number, k: number): void {
    const ctx = this.ctx;
    ctx.beginPath();
    ctx.moveTo(sx - k, sy - k);
    ctx.lineTo(sx + k, sy + k);
    ctx.moveTo(sx + k, sy - k);
    ctx.lineTo(sx - k, sy + k);
    ctx.stroke();
  }

  private drawArrow(sx: number, sy: number, theta: number, length: number, color: string, width: number): void {
    const ctx = this.ctx;
    const ux = Math.cos(theta);
    const uy = -Math.sin(theta); // screen y is down
    const ex = sx + ux * length;
    const ey = sy + uy * length;
    const head = Math.min(12, 4 + length * 0.25);
    ctx.strokeStyle = color;
    ctx.fillStyle = color;
    ctx.lineWidth = width;
    ctx.lineCap = 'round';
    ctx.beginPath();
    ctx.moveTo(sx, sy);
    ctx.lineTo(ex - ux * head * 0.6, ey - uy * head * 0.6);
    ctx.stroke();
    ctx.lineCap = 'butt';
    ctx.beginPath();
    ctx.moveTo(ex, ey);
    ctx.lineTo(ex - ux * head - uy * head * 0.5, ey - uy * head + ux * head * 0.5);
    ctx.lineTo(ex - ux * head + uy * head * 0.5, ey - uy * head - ux * head * 0.5);
    ctx.closePath();
    ctx.fill();
  }

  private drawObstacles(): void {
    if (this.obstacles.length === 0) return;
    const ctx = this.ctx;
    const v = this.view;
    for (const o of this.obstacles) {
      const [sx, sy] = v.toScreen(o.x, o.y);
      const r = Math.max(2, o.radius * v.scale);
      ctx.beginPath();
      ctx.arc(sx, sy, r, 0, 2 * Math.PI);
      ctx.fillStyle = COLORS.obstacleFill;
      ctx.fill();
      ctx.strokeStyle = COLORS.obstacleStroke;
      ctx.lineWidth = 2;
      ctx.stroke();
      if (r > 8) {
        ctx.fillStyle = '#fff7ed';
        ctx.font = '600 10px system-ui, sans-serif';
        ctx.textAlign = 'center';
        ctx.textBaseline = 'middle';
        ctx.fillText(String(o.id), sx, sy);
        ctx.textAlign = 'start';
        ctx.textBaseline = 'alphabetic';
      }
    }
  }

  /** A wedge of +-2 sigma(theta) around the estimated heading. */
  private drawHeadingWedge(pose: Pose2D, cov: readonly number[]): void {
    const ctx = this.ctx;
    const v = this.view;
    const [cx, cy] = v.toScreen(pose.x, pose.y);
    const sigmaTheta = headingSigma(cov);
    if (sigmaTheta !== null) {
      const half = Math.min(Math.PI, UNCERTAINTY_SIGMAS * sigmaTheta);
      const radius = Math.max(26, FOOTPRINT_M * 1.25 * v.scale);
      ctx.beginPath();
      ctx.moveTo(cx, cy);
      // Screen angles are the map angles negated (y down).
      ctx.arc(cx, cy, radius, -pose.theta - Math.max(half, 0.004), -pose.theta + Math.max(half, 0.004));
      ctx.closePath();
      ctx.fillStyle = COLORS.wedgeFill;
      ctx.fill();
      ctx.strokeStyle = COLORS.wedgeStroke;
      ctx.lineWidth = 1;
      ctx.stroke();
    }
  }

  /** The 2-sigma ellipse of the x-y covariance around the estimated position. */
  private drawCovarianceEllipse(pose: Pose2D, cov: readonly number[]): void {
    const ctx = this.ctx;
    const v = this.view;
    const [cx, cy] = v.toScreen(pose.x, pose.y);
    const ellipse = covarianceEllipse(cov, UNCERTAINTY_SIGMAS);
    if (ellipse) {
      // Sub-pixel uncertainty still shows as a small ring at the estimate.
      const rx = Math.max(3, ellipse.major * v.scale);
      const ry = Math.max(3, ellipse.minor * v.scale);
      ctx.beginPath();
      ctx.ellipse(cx, cy, rx, ry, -ellipse.angle, 0, 2 * Math.PI);
      ctx.fillStyle = COLORS.covFill;
      ctx.fill();
      ctx.strokeStyle = COLORS.covStroke;
      ctx.lineWidth = 1.5;
      ctx.stroke();
    }
  }

  private drawErrorMark(): void {
    const mark = this.errorMark;
    if (!mark) return;
    if (performance.now() > mark.until) {
      this.errorMark = null;
      return;
    }
    const ctx = this.ctx;
    const [sx, sy] = this.view.toScreen(mark.x, mark.y);
    ctx.strokeStyle = 'rgba(11, 15, 20, 0.8)';
    ctx.lineWidth = 5;
    const cross = () => this.strokeCross(sx, sy, 8);
    cross();
    ctx.strokeStyle = COLORS.error;
    ctx.lineWidth = 2.5;
    cross();
  }

  /** The preview of an active press-and-drag tool. */
  private drawPress(): void {
    const tool = this.tool;
    if (!tool) return;
    const ctx = this.ctx;
    const v = this.view;
    const press = this.press;
    const at = press ? [press.x, press.y] : this.cursor;
    if (!at) return;
    const [sx, sy] = v.toScreen(at[0]!, at[1]!);
    ctx.strokeStyle = tool.color;
    ctx.fillStyle = tool.color;
    ctx.lineWidth = 2;
    if (tool.radius !== undefined) {
      ctx.setLineDash(press ? [] : [4, 3]);
      ctx.beginPath();
      ctx.arc(sx, sy, Math.max(3, tool.radius * v.scale), 0, 2 * Math.PI);
      ctx.stroke();
      ctx.setLineDash([]);
    } else {
      ctx.beginPath();
      ctx.arc(sx, sy, press ? 6 : 4, 0, 2 * Math.PI);
      if (press) ctx.fill();
      else ctx.stroke();
    }
    if (press && tool.heading) {
      const heading = dragHeading(press, { x: press.cx, y: press.cy }, v.scale);
      if (heading !== null) {
        const length = Math.hypot(press.cx - press.x, press.cy - press.y) * v.scale;
        this.drawArrow(sx, sy, heading, Math.max(length, 20), tool.color, 2.5);
        const label = `${((heading * 180) / Math.PI).toFixed(0)}°`;
        ctx.font = '600 11px system-ui, sans-serif';
        ctx.fillStyle = tool.color;
        ctx.fillText(label, sx + 10, sy - 10);
      }
    }
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
