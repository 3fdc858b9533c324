import { describe, expect, it, vi } from 'vitest';
import { defaultSwitches, drawLayers, LAYER_SWITCHES } from '../src/map/layer';
import type { LayerFilter, MapFrame, MapLayer, MapScene } from '../src/map/layer';
import { createMapLayers } from '../src/map/layers';
import { paintTileInto } from '../src/map/layers/map_tiles';
import { OCCUPANCY_PALETTE } from '../src/map/layers/map_image';
import { ViewTransform } from '../src/map/view_transform';
import { particlesFromJson } from '../src/particles';
import { PolygonDraft } from '../src/polygon_tool';
import { TileStore } from '../src/tile_store';
import { robotBody } from '../src/tricycle';

/** The drawing order, bottom first: the map (whole or being built), the costmaps, zones, sensors, plans, robot, tools. */
const EXPECTED_ORDER = [
  'grid',
  'map',
  'mapTiles',
  'costmap',
  'localCostmap',
  'ipabd',
  'zones',
  'sonar',
  'ir',
  'scan',
  'trajectory',
  'obstacles',
  'path',
  'goal',
  'trail',
  'particles',
  'headingWedge',
  'truth',
  'robot',
  'covariance',
  'errorMark',
  'polygonDraft',
  'toolPreview',
  'scaleBar',
  'cursorReadout',
];

const ROBOT_LAYERS = ['trail', 'particles', 'headingWedge', 'truth', 'robot', 'covariance'];

interface RecordingContext {
  ctx: CanvasRenderingContext2D;
  /** Every method called, as "method" (setTransform with its arguments). */
  calls: string[];
}

/** A 2D context that accepts every call and property and records the calls. */
function recordingContext(): RecordingContext {
  const calls: string[] = [];
  const target: Record<string, unknown> = {};
  const ctx = new Proxy(target, {
    get(_, key: string) {
      if (key in target) return target[key];
      return (...args: unknown[]) => {
        calls.push(key === 'setTransform' ? `setTransform(${args.join(',')})` : key);
        return key === 'measureText' ? { width: 40 } : undefined;
      };
    },
    set(_, key: string, value) {
      target[key] = value;
      return true;
    },
  });
  return { ctx: ctx as unknown as CanvasRenderingContext2D, calls };
}

function frameOf(ctx: CanvasRenderingContext2D, scene: Partial<MapScene> = {}): MapFrame {
  return {
    ctx,
    view: new ViewTransform(50, 400, 300),
    dpr: 2,
    width: 800,
    height: 600,
    canvas: { dataset: {} } as HTMLCanvasElement,
    scene: { map: null, tiles: new TileStore(), pose: null, cov: null, pointer: { tool: null, press: null, cursor: null }, ...scene },
  };
}

const everything: LayerFilter = {
  switches: Object.fromEntries(LAYER_SWITCHES.map((name) => [name, true])) as LayerFilter['switches'],
  showRobot: true,
};

/** Replaces every layer's draw by one that records its id. */
function spyOnDraws(layers: MapLayer[]): string[] {
  const drawn: string[] = [];
  for (const layer of layers) vi.spyOn(layer, 'draw').mockImplementation(() => drawn.push(layer.id));
  return drawn;
}

describe('layer registry', () => {
  it('registers every layer once, under its id', () => {
    const layers = createMapLayers(() => {});
    const entries = Object.entries(layers);
    for (const [key, layer] of entries) expect(layer.id).toBe(key);
    expect(new Set(entries.map(([, layer]) => layer.id)).size).toBe(entries.length);
    expect(new Set(entries.map(([, layer]) => layer)).size).toBe(entries.length);
    expect(entries.map(([key]) => key)).toEqual(EXPECTED_ORDER);
  });

  it('gives every view its own layers', () => {
    const a = createMapLayers(() => {});
    const b = createMapLayers(() => {});
    for (const key of Object.keys(a) as (keyof typeof a)[]) expect(a[key]).not.toBe(b[key]);
  });

  it('draws the layers in registry order, each once per frame, from the CSS-pixel transform', () => {
    const layers: MapLayer[] = Object.values(createMapLayers(() => {}));
    const drawn = spyOnDraws(layers);
    const { ctx, calls } = recordingContext();
    drawLayers(layers, frameOf(ctx), everything);
    expect(drawn).toEqual(EXPECTED_ORDER);
    expect(calls).toEqual(EXPECTED_ORDER.map(() => 'setTransform(2,0,0,2,0,0)'));
  });

  it('leaves out the layers whose switch is off', () => {
    for (const name of LAYER_SWITCHES) {
      const layers: MapLayer[] = Object.values(createMapLayers(() => {}));
      const drawn = spyOnDraws(layers);
      drawLayers(layers, frameOf(recordingContext().ctx), { ...everything, switches: { ...everything.switches, [name]: false } });
      const hidden = layers.filter((layer) => layer.toggle === name).map((layer) => layer.id);
      expect(hidden.length).toBeGreaterThan(0);
      expect(drawn).toEqual(EXPECTED_ORDER.filter((id) => !hidden.includes(id)));
    }
  });

  it('leaves out the robot on views without one', () => {
    const layers: MapLayer[] = Object.values(createMapLayers(() => {}));
    const drawn = spyOnDraws(layers);
    drawLayers(layers, frameOf(recordingContext().ctx), { ...everything, showRobot: false });
    expect(drawn).toEqual(EXPECTED_ORDER.filter((id) => !ROBOT_LAYERS.includes(id)));
  });

  it('asks for a redraw when a layer gets data', () => {
    const redraw = vi.fn();
    const layers = createMapLayers(redraw);
    layers.sonar.set([]);
    layers.path.set([[0, 0], [1, 1]]);
    layers.trail.clear();
    expect(redraw).toHaveBeenCalledTimes(3);
  });
});

describe('layers', () => {
  it('draw their data without a map (no DOM needed)', () => {
    const layers = createMapLayers(() => {});
    layers.scan.set({ angleMin: -1, angleIncrement: 0.5, rangeMin: 0.1, rangeMax: 10, sensorPose: { x: 0, y: 0, theta: 0 }, ranges: Float32Array.of(1, 2, 3, 4, 5) });
    layers.sonar.set([{ x: 0, y: 0, theta: 0, cone: 0.3, range: 1, range_min: 0.1, range_max: 5 }]);
    layers.trajectory.set([{ x: 0, y: 0 }, { x: 1, y: 1 }]);
    layers.obstacles.set([{ id: 1, x: 2, y: 2, radius: 0.25 }]);
    layers.path.set([[0, 0], [1, 0], [2, 1]]);
    layers.goal.set({ x: 2, y: 1, theta: 0.5, status: 'failed' });
    layers.trail.add(0, 0);
    layers.trail.add(1, 0);
    layers.truth.set({ x: 0.1, y: 0, theta: 0 });
    layers.ir.set([{ x: 0, y: 0, theta: 1, cone: 0.2, range: 0.3, range_min: 0.05, range_max: 0.8 }]);
    layers.particles.set(particlesFromJson({ count: 2, total: 100, particles: [[0, 0, 0, 0.7], [1, 0, 1, 0.3]] }));
    layers.zones.set([{ id: 1, name: 'dock', polygon: [[0, 0], [2, 0], [2, 2]] }]);
    const draft = new PolygonDraft();
    draft.start();
    draft.click([0, 0], 0.01);
    draft.click([1, 0], 0.01);
    draft.move([1, 1]);
    layers.polygonDraft.attach(draft);
    const scene = { pose: { x: 0, y: 0, theta: 0 }, cov: [0.04, 0, 0, 0, 0.01, 0, 0, 0, 0.02], pointer: { tool: null, press: null, cursor: [1, 2] as [number, number] } };
    // Without data (map, costmaps, tiles: painting them needs a DOM) these draw nothing.
    const silent = new Set(['map', 'mapTiles', 'costmap', 'localCostmap', 'ipabd', 'errorMark', 'toolPreview']);
    for (const layer of Object.values(layers)) {
      const { ctx, calls } = recordingContext();
      layer.draw(frameOf(ctx, scene));
      if (silent.has(layer.id)) expect(calls, layer.id).toEqual([]);
      else expect(calls.length, layer.id).toBeGreaterThan(0);
    }
  });

  it('publish what they drew on the canvas: tiles, costmap cells, particles, zones', () => {
    const layers = createMapLayers(() => {});
    const frame = frameOf(recordingContext().ctx);
    for (const layer of Object.values(layers)) layer.draw(frame);
    expect(frame.canvas.dataset).toMatchObject({ tiles: '0', costmapCells: '0', localCostmapCells: '0', particles: '0', zones: '0' });
    layers.particles.set(particlesFromJson({ count: 3, total: 3, particles: [[0, 0, 0, 1], [1, 1, 0, 1], [NaN, 0, 0, 1]] }));
    layers.zones.set([{ id: 1, name: '', polygon: [[0, 0], [1, 0], [1, 1]] }, { id: 2, name: '', polygon: [[0, 0], [1, 0]] }]);
    layers.particles.draw(frame);
    layers.zones.draw(frame);
    expect(frame.canvas.dataset).toMatchObject({ particles: '2', zones: '1' });
    expect(layers.particles.setsDrawn).toBe(1);
    layers.particles.draw(frame);
    expect(layers.particles.setsDrawn).toBe(1);
  });

  it('start with the switches of the Live page: the global costmap off, the rest on', () => {
    const defaults = defaultSwitches();
    expect(Object.keys(defaults).sort()).toEqual([...LAYER_SWITCHES].sort());
    expect(Object.entries(defaults).filter(([, on]) => !on).map(([name]) => name)).toEqual(['costmap']);
  });

  it('paint a tile into the mosaic at its lattice offset, row 0 at the bottom', () => {
    const pixels = new Uint32Array(4 * 4);
    paintTileInto(pixels, 4, Uint8Array.of(0, 100, 255, 50), 2, 2, 1);
    expect(pixels[1 * 4 + 2]).toBe(OCCUPANCY_PALETTE[0]);
    expect(pixels[1 * 4 + 3]).toBe(OCCUPANCY_PALETTE[100]);
    expect(pixels[2 * 4 + 2]).toBe(OCCUPANCY_PALETTE[255]);
    expect(pixels[2 * 4 + 3]).toBe(OCCUPANCY_PALETTE[50]);
    expect(pixels.filter((p) => p !== 0).length).toBe(4);
  });

  it('publishes the IPaBD cells drawn on the canvas (none without a grid)', () => {
    const layers = createMapLayers(() => {});
    const frame = frameOf(recordingContext().ctx);
    layers.ipabd.draw(frame);
    expect(frame.canvas.dataset.ipabdCells).toBe('0');
  });

  it('count each scan drawn once, however often it is redrawn', () => {
    const layers = createMapLayers(() => {});
    const scan = { angleMin: 0, angleIncrement: 0.1, rangeMin: 0.1, rangeMax: 10, sensorPose: { x: 0, y: 0, theta: 0 }, ranges: Float32Array.of(1, 1) };
    const frame = frameOf(recordingContext().ctx);
    layers.scan.set(scan);
    layers.scan.draw(frame);
    layers.scan.draw(frame);
    expect(layers.scan.scansDrawn).toBe(1);
    layers.scan.set(scan);
    layers.scan.draw(frame);
    expect(layers.scan.scansDrawn).toBe(2);
  });
});

describe('robot layer', () => {
  const pose = { x: 1, y: 2, theta: 0.3 };
  const tricycle = robotBody({ kinematics: 'tricycle_t1', geometry: { wheelbase_m: 0.9, footprint_length_m: 1.3, footprint_width_m: 0.7, footprint_offset_m: 0.45 } });
  const count = (calls: string[], name: string) => calls.filter((c) => c === name).length;

  it('draws a differential robot as the filled square with its heading', () => {
    const layers = createMapLayers(() => {});
    const { ctx, calls } = recordingContext();
    layers.robot.draw(frameOf(ctx, { pose }));
    expect(count(calls, 'fill')).toBe(1);
  });

  it('draws a tricycle as its body and three wheels; the ghost as the outline alone', () => {
    const layers = createMapLayers(() => {});
    expect(layers.robot.setBody(tricycle)).toBe(true);
    expect(layers.robot.setBody(robotBody({ kinematics: 'tricycle_t1', geometry: { wheelbase_m: 0.9, footprint_length_m: 1.3, footprint_width_m: 0.7, footprint_offset_m: 0.45 } }))).toBe(false);
    layers.robot.steering = 0.4;
    const { ctx, calls } = recordingContext();
    layers.robot.draw(frameOf(ctx, { pose }));
    expect(count(calls, 'fill')).toBe(4); // body + 2 rear wheels + front wheel
    const redraw = vi.fn();
    const ghost = createMapLayers(redraw).truth;
    ghost.setBody(tricycle);
    ghost.set(pose);
    const recorded = recordingContext();
    ghost.draw(frameOf(recorded.ctx));
    expect(count(recorded.calls, 'fill')).toBe(0);
    expect(count(recorded.calls, 'stroke')).toBe(1);
  });
});
