// Canvas view of the map frame: the occupancy grid and everything drawn over it (layers/), panned
// by dragging and zoomed with the wheel about the cursor. This class wires the canvas (size, draw
// loop), the viewport (view transform and fitting), the pointer input and the layers, and holds
// what several of them share: the map (whole, or the tiles of one being built) and the estimated
// pose.

import { mapCorners } from '../frames';
import type { MapGrid, Pose2D } from '../frames';
import { TileStore } from '../tile_store';
import type { TileUpdate } from '../tiles';
import type { RobotBody } from '../tricycle';
import { MapCanvas } from './canvas';
import { BACKGROUND } from './colors';
import { MapInput } from './input';
import type { MapTool } from './input';
import { defaultSwitches, drawLayers } from './layer';
import type { LayerSwitch, LayerSwitches, MapScene } from './layer';
import { createMapLayers } from './layers';
import type { MapLayers } from './layers';
import { boundsOf, grow } from './view_transform';
import type { Bounds, ViewTransform } from './view_transform';
import { Viewport } from './viewport';

export interface MapViewOptions {
  /** False for a view of recorded data (the Runs page): no robot, trail, ghost or uncertainty. */
  showRobot?: boolean;
}

/** Without a map, the first fit shows this many metres around the robot. */
const ROBOT_SURROUNDINGS_M = 5;
/** Margin (m) around a trajectory fitted into the view. */
const TRAJECTORY_MARGIN_M = 1;

export class MapView {
  /** The drawn layers, bottom first; a layer's own data is set through it (layers.scan.set(scan)). */
  readonly layers: MapLayers;
  framesDrawn = 0;
  /** A map was set (window.__mobot.mapShown). */
  mapShown = false;
  private readonly surface: MapCanvas;
  private readonly viewport = new Viewport();
  private readonly input: MapInput;
  private readonly scene: MapScene;
  private readonly switches: LayerSwitches = defaultSwitches();

  constructor(
    readonly canvas: HTMLCanvasElement,
    private readonly options: MapViewOptions = {},
  ) {
    this.surface = new MapCanvas(canvas, {
      resized: (width, height) => this.viewport.resize(width, height),
      render: () => this.draw(),
    });
    this.layers = createMapLayers(() => this.invalidate());
    this.input = new MapInput(canvas, this.viewport, { redraw: () => this.invalidate(), fit: () => this.fit() });
    this.scene = { map: null, tiles: new TileStore(), pose: null, cov: null, pointer: this.input.pointer };
    this.surface.start();
  }

  /** Map frame <-> CSS pixels of the canvas. */
  get view(): ViewTransform {
    return this.viewport.transform;
  }

  destroy(): void {
    this.surface.destroy();
  }

  // ---- shared data ----

  /** A whole map: it replaces the tiles of a map being built. */
  setMap(map: MapGrid): void {
    const previous = this.scene.map;
    this.scene.map = map;
    const hadTiles = this.scene.tiles.size > 0;
    this.scene.tiles.clear();
    const changedShape =
      !previous ||
      previous.id !== map.id ||
      previous.width !== map.width ||
      previous.height !== map.height ||
      previous.resolution !== map.resolution;
    // A map update (new cells, same grid) keeps the view; another map is fitted.
    if (changedShape || hadTiles) this.viewport.contentChanged();
    this.mapShown = true;
    this.invalidate();
  }

  /** Changed tiles of the map being built; a view that follows the content grows with the map. */
  setTiles(update: TileUpdate): void {
    const result = this.scene.tiles.apply(update);
    if (result.reset || result.grew) this.viewport.contentChanged();
    if (this.scene.tiles.size > 0) this.mapShown = true;
    this.invalidate();
  }

  /** Drops the tiles (mapping ended): the whole map shows again. */
  clearTiles(): void {
    if (this.scene.tiles.size === 0) return;
    this.scene.tiles.clear();
    this.viewport.contentChanged();
    this.invalidate();
  }

  /** The tiles of the map being built (read-only use). */
  get tiles(): TileStore {
    return this.scene.tiles;
  }

  getMap(): MapGrid | null {
    return this.scene.map;
  }

  /**
   * The estimated pose, whatever the estimator; a `cov` of 9 numbers (3x3, x y theta) adds the
   * uncertainty layers, a tricycle's `steering_rad` turns its front wheel.
   */
  setPose(pose: Pose2D & { cov?: readonly number[]; steering_rad?: number }): void {
    this.scene.pose = pose;
    this.scene.cov = Array.isArray(pose.cov) && pose.cov.length === 9 ? pose.cov : null;
    if (typeof pose.steering_rad === 'number' && Number.isFinite(pose.steering_rad)) this.layers.robot.steering = pose.steering_rad;
    this.layers.trail.add(pose.x, pose.y);
    this.invalidate();
  }

  /** What the robot looks like (differential footprint or a tricycle's body), estimate and ghost. */
  setRobotBody(body: RobotBody): void {
    this.layers.truth.setBody(body);
    if (this.layers.robot.setBody(body)) this.invalidate();
  }

  /** A tricycle's steering angle when no pose carried one (the status topic). */
  setSteering(steering: number): void {
    if (!Number.isFinite(steering) || steering === this.layers.robot.steering) return;
    this.layers.robot.steering = steering;
    this.invalidate();
  }

  /** A layer checkbox of the Live page. */
  setLayerShown(name: LayerSwitch, shown: boolean): void {
    this.switches[name] = shown;
    this.invalidate();
  }

  /** Activates a press-and-drag tool (null: back to panning). */
  setTool(tool: MapTool | null): void {
    this.input.setTool(tool);
  }

  get activeTool(): string | null {
    return this.input.pointer.tool?.name ?? null;
  }

  /** Asks for a redraw. */
  invalidate(): void {
    this.surface.invalidate();
  }

  // ---- view ----

  /** Fits the map (or, without one, the robot's surroundings) into the canvas. */
  fit(): void {
    this.viewport.requestFit();
    this.invalidate();
  }

  /** Shows map points with a margin around them (a run's trajectory on a view without a map). */
  fitPoints(points: readonly { x: number; y: number }[]): void {
    if (points.length < 2) return;
    const bounds = boundsOf(points.map((p) => [p.x, p.y] as [number, number]));
    if (bounds) this.viewport.fitNow(grow(bounds, TRAJECTORY_MARGIN_M));
    this.invalidate();
  }

  centerOnRobot(): void {
    const pose = this.scene.pose;
    if (!pose) return;
    this.viewport.centerOn(pose.x, pose.y);
    this.invalidate();
  }

  /** Zooms about the centre of the canvas. */
  zoom(factor: number): void {
    this.viewport.zoomAtCentre(factor);
    this.invalidate();
  }

  /** Map frame -> CSS pixels relative to the browser viewport (for the browser test). */
  mapToClient(x: number, y: number): [number, number] {
    const rect = this.canvas.getBoundingClientRect();
    const [sx, sy] = this.view.toScreen(x, y);
    return [rect.left + sx, rect.top + sy];
  }

  /** Whether the robot's pose is inside the visible canvas (for the browser test). */
  robotVisible(): boolean {
    const pose = this.scene.pose;
    return pose !== null && this.viewport.shows(pose.x, pose.y);
  }

  // ---- drawing ----

  /** Draws a frame now (the canvas's draw loop calls this after invalidate()). */
  draw(): void {
    this.viewport.applyPendingFit(() => this.contentBounds());
    this.surface.clear(BACKGROUND);
    const frame = {
      ctx: this.surface.ctx,
      view: this.view,
      dpr: this.surface.dpr,
      width: this.viewport.width,
      height: this.viewport.height,
      canvas: this.canvas,
      scene: this.scene,
    };
    drawLayers(Object.values(this.layers), frame, { switches: this.switches, showRobot: this.options.showRobot !== false });
    this.framesDrawn++;
  }

  /** What a fit shows: the map being built, else the whole map, else the robot's surroundings, else nothing yet. */
  private contentBounds(): Bounds | null {
    const { map, pose, tiles } = this.scene;
    const built = tiles.bounds();
    if (built) return built;
    if (map) return boundsOf(mapCorners(map));
    if (pose) return grow({ minX: pose.x, minY: pose.y, maxX: pose.x, maxY: pose.y }, ROBOT_SURROUNDINGS_M);
    return null;
  }
}
