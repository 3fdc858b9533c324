// The registry of map layers. The order of the entries is the drawing order, bottom first; each
// key is its layer's id and the typed handle through which the layer's data is set
// (mapView.layers.scan.set(scan)). A new layer is a file in this folder and one line here.

import type { MapLayer, Redraw } from '../layer';
import { CostmapLayer } from './costmap';
import { CovarianceEllipseLayer } from './covariance_ellipse';
import { CursorReadoutLayer } from './cursor_readout';
import { ErrorMarkLayer } from './error_mark';
import { GoalLayer } from './goal';
import { GridLayer } from './grid';
import { HeadingWedgeLayer } from './heading_wedge';
import { IpabdObstaclesLayer } from './ipabd_obstacles';
import { IrLayer } from './ir';
import { KeepoutZonesLayer } from './keepout_zones';
import { MapImageLayer } from './map_image';
import { MapTilesLayer } from './map_tiles';
import { ObstaclesLayer } from './obstacles';
import { ParticlesLayer } from './particles';
import { PathLayer } from './path';
import { PolygonDraftLayer } from './polygon_draft';
import { RobotLayer } from './robot';
import { ScaleBarLayer } from './scale_bar';
import { ScanLayer } from './scan';
import { SonarLayer } from './sonar';
import { ToolPreviewLayer } from './tool_preview';
import { TrailLayer } from './trail';
import { TrajectoryLayer } from './trajectory';
import { TruthLayer } from './truth';

/** A fresh set of layers for one map view; `redraw` asks that view for a frame. */
export function createMapLayers(redraw: Redraw) {
  return {
    grid: new GridLayer(),
    map: new MapImageLayer(),
    mapTiles: new MapTilesLayer(),
    costmap: new CostmapLayer('costmap', redraw),
    localCostmap: new CostmapLayer('localCostmap', redraw),
    ipabd: new IpabdObstaclesLayer(redraw),
    zones: new KeepoutZonesLayer(redraw),
    sonar: new SonarLayer(redraw),
    ir: new IrLayer(redraw),
    scan: new ScanLayer(redraw),
    trajectory: new TrajectoryLayer(redraw),
    obstacles: new ObstaclesLayer(redraw),
    path: new PathLayer(redraw),
    goal: new GoalLayer(redraw),
    trail: new TrailLayer(redraw),
    particles: new ParticlesLayer(redraw),
    headingWedge: new HeadingWedgeLayer(),
    truth: new TruthLayer(redraw),
    robot: new RobotLayer(),
    covariance: new CovarianceEllipseLayer(),
    errorMark: new ErrorMarkLayer(redraw),
    polygonDraft: new PolygonDraftLayer(),
    toolPreview: new ToolPreviewLayer(),
    scaleBar: new ScaleBarLayer(),
    cursorReadout: new CursorReadoutLayer(),
  } satisfies Record<string, MapLayer>;
}

export type MapLayers = ReturnType<typeof createMapLayers>;
