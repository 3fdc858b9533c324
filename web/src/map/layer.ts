// What a drawn layer of the map view is, what it is given to draw a frame, and the one loop that
// draws the registered layers bottom to top (layers/index.ts holds the list).

import type { MapGrid, Pose2D } from '../frames';
import type { TileStore } from '../tile_store';
import type { PointerState } from './input';
import type { ViewTransform } from './view_transform';

/** The Live page's layer checkboxes (#layer-<name>); a layer may belong to one of them. */
export const LAYER_SWITCHES = ['scan', 'sonar', 'ir', 'trail', 'truth', 'path', 'cov', 'particles', 'costmap', 'localCostmap', 'zones'] as const;
export type LayerSwitch = (typeof LAYER_SWITCHES)[number];
export type LayerSwitches = Record<LayerSwitch, boolean>;

/** Which switches start on (the checkboxes of index.html say the same): the global costmap hides the map's colours. */
export function defaultSwitches(): LayerSwitches {
  return { scan: true, sonar: true, ir: true, trail: true, truth: true, path: true, cov: true, particles: true, costmap: false, localCostmap: true, zones: true };
}

/** What more than one layer reads; the rest of a layer's data is its own (set through the layer). */
export interface MapScene {
  /** The whole map (the `map` topic); not drawn while `tiles` holds a map being built. */
  map: MapGrid | null;
  /** The map being built while mapping, as tiles (empty otherwise). */
  tiles: TileStore;
  /** The estimated pose of the robot. */
  pose: Pose2D | null;
  /** Its 3x3 covariance (x, y, theta; row-major), or null when the pose came without one. */
  cov: readonly number[] | null;
  pointer: Readonly<PointerState>;
}

/** One frame of one map view, as every layer gets it. */
export interface MapFrame {
  ctx: CanvasRenderingContext2D;
  /** Map frame <-> CSS pixels of this frame. */
  view: ViewTransform;
  /** Device pixels per CSS pixel. */
  dpr: number;
  /** Canvas size in CSS pixels. */
  width: number;
  height: number;
  /** The canvas element, for layers that publish what they drew as data-* attributes. */
  canvas: HTMLCanvasElement;
  scene: Readonly<MapScene>;
}

/**
 * A drawn layer. Each draw starts in CSS pixels (ctx transform = dpr scale); a layer drawing in
 * map metres sets its own transform. Line dash, alpha and text alignment are left as found.
 */
export interface MapLayer {
  /** Unique; the layer's key in the registry. */
  readonly id: string;
  /** The checkbox that hides this layer, if any. */
  readonly toggle?: LayerSwitch;
  /** Part of the robot's drawing: absent from views without a robot (the Runs page). */
  readonly showsRobot?: boolean;
  draw(frame: MapFrame): void;
}

/** Asks the view owning a layer for a new frame (a layer's data changed). */
export type Redraw = () => void;

export interface LayerFilter {
  switches: Readonly<LayerSwitches>;
  showRobot: boolean;
}

export function isLayerShown(layer: MapLayer, filter: LayerFilter): boolean {
  if (layer.showsRobot && !filter.showRobot) return false;
  return layer.toggle === undefined || filter.switches[layer.toggle];
}

/** Draws the shown layers in the order given (bottom first). */
export function drawLayers(layers: Iterable<MapLayer>, frame: MapFrame, filter: LayerFilter): void {
  for (const layer of layers) {
    if (!isLayerShown(layer, filter)) continue;
    frame.ctx.setTransform(frame.dpr, 0, 0, frame.dpr, 0, 0);
    layer.draw(frame);
  }
}
