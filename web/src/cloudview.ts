// The 3D view of a sweep (three.js, loaded on demand by the 3D page so the Live page does not pay
// for it): the cloud as Points coloured by height, the robot as a 0.6 x 0.6 x 1.2 m box at its pose,
// the active map as a floor texture, and OrbitControls (left drag orbits, right drag pans, wheel
// zooms). The map frame is used as is: z up. Renders only when something changed.

import {
  BoxGeometry,
  BufferAttribute,
  BufferGeometry,
  CanvasTexture,
  ColorManagement,
  DynamicDrawUsage,
  EdgesGeometry,
  Group,
  LinearFilter,
  LinearSRGBColorSpace,
  LineBasicMaterial,
  LineSegments,
  Mesh,
  MeshBasicMaterial,
  NearestFilter,
  NoColorSpace,
  PerspectiveCamera,
  PlaneGeometry,
  Points,
  PointsMaterial,
  Scene,
  Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { paintFloor } from './cloud';
import type { CloudBuffer } from './cloud';
import type { MapGrid, Pose2D } from './frames';
import { mapCorners } from './frames';

/** The robot's body (docs/algorithms.md: 0.6 m square, 1.2 m tall; the 3D collision check uses the same). */
export const ROBOT_SIZE_M = { x: 0.6, y: 0.6, z: 1.2 } as const;
const POINT_SIZE_M = 0.05;
/** Pose updates (50 Hz) alone redraw at most this often: SwiftShader / weak GPUs with 72 000 points. */
const POSE_REDRAW_MS = 100;
const BACKGROUND = 0x0b0f14;
const FOV_DEG = 50;

// Colours are given and wanted as sRGB bytes (the legend is CSS): no linear conversion anywhere.
ColorManagement.enabled = false;

interface Box3 {
  minX: number;
  minY: number;
  minZ: number;
  maxX: number;
  maxY: number;
  maxZ: number;
}

export class CloudView {
  /** Points in the last rendered frame (also the container's data-points). */
  drawnPoints = 0;
  renders = 0;

  private readonly renderer: WebGLRenderer;
  private readonly scene = new Scene();
  private readonly camera = new PerspectiveCamera(FOV_DEG, 1, 0.05, 500);
  private readonly controls: OrbitControls;
  private readonly material = new PointsMaterial({ size: POINT_SIZE_M, vertexColors: true, sizeAttenuation: true });
  private geometry = new BufferGeometry();
  private readonly points: Points;
  private readonly robot = new Group();
  private floor: Mesh<PlaneGeometry, MeshBasicMaterial> | null = null;
  private map: MapGrid | null = null;
  private pose: Pose2D | null = null;
  /** What of the cloud buffer the GPU holds. */
  private uploaded = { generation: -1, colorVersion: -1, clears: -1, count: 0 };
  private dirty = true;
  private poseChanged = false;
  private lastRenderAt = 0;
  private active = false;
  private frame = 0;
  /** The user orbited / zoomed / panned: automatic fitting stops until "Reset view". */
  private userMoved = false;
  /** Fit the camera at the next render (map or sweep changed while the user had not moved it). */
  private fitPending = false;
  private width = 0;
  private height = 0;
  private readonly resizeObserver: ResizeObserver;

  constructor(
    private readonly container: HTMLElement,
    private readonly cloud: CloudBuffer,
  ) {
    // Throws without WebGL; the page shows that instead of the view.
    this.renderer = new WebGLRenderer({ antialias: false, powerPreference: 'high-performance' });
    this.renderer.outputColorSpace = LinearSRGBColorSpace;
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(BACKGROUND);
    this.renderer.domElement.dataset.testid = 'cloud-canvas';
    container.prepend(this.renderer.domElement);

    this.camera.up.set(0, 0, 1); // before the controls: they orbit about camera.up
    this.camera.position.set(-8, -10, 9);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.maxDistance = 300;
    this.controls.addEventListener('change', () => (this.dirty = true));
    this.controls.addEventListener('start', () => (this.userMoved = true));

    this.points = new Points(this.geometry, this.material);
    // The bounding sphere is not kept up to date while the cloud grows: never cull.
    this.points.frustumCulled = false;
    this.scene.add(this.points);
    this.scene.add(this.makeRobot());
    this.robot.visible = false;

    this.resizeObserver = new ResizeObserver(() => (this.dirty = true));
    this.resizeObserver.observe(container);
    this.fit();
  }

  /** Starts (shown page) or stops (hidden page) drawing. */
  setActive(active: boolean): void {
    if (active === this.active) return;
    this.active = active;
    cancelAnimationFrame(this.frame);
    if (active) {
      this.dirty = true;
      this.frame = requestAnimationFrame(this.loop);
    }
  }

  /** The cloud buffer changed (points appended, cleared or reloaded). */
  sync(): void {
    if (this.uploaded.clears !== this.cloud.clears && !this.userMoved) this.fitPending = true;
    this.dirty = true;
  }

  setPose(pose: Pose2D): void {
    this.pose = pose;
    this.robot.visible = true;
    this.robot.position.set(pose.x, pose.y, ROBOT_SIZE_M.z / 2);
    this.robot.rotation.set(0, 0, pose.theta);
    this.poseChanged = true;
  }

  setMap(map: MapGrid): void {
    const previous = this.map;
    this.map = map;
    if (this.floor) {
      this.scene.remove(this.floor);
      this.floor.geometry.dispose();
      this.floor.material.map?.dispose();
      this.floor.material.dispose();
      this.floor = null;
    }
    if (map.width > 0 && map.height > 0) this.floor = this.makeFloor(map);
    if (this.floor) this.scene.add(this.floor);
    if (!this.userMoved && (!previous || previous.id !== map.id)) this.fitPending = true;
    this.dirty = true;
  }

  /** Shows the whole scene (cloud, map, robot) from the south-west, above. */
  resetView(): void {
    this.userMoved = false;
    this.fit();
  }

  destroy(): void {
    this.setActive(false);
    this.resizeObserver.disconnect();
    this.controls.dispose();
    this.geometry.dispose();
    this.material.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }

  // ---- internals ----

  private loop = (): void => {
    this.frame = requestAnimationFrame(this.loop);
    this.resize();
    const now = performance.now();
    const poseDue = this.poseChanged && now - this.lastRenderAt >= POSE_REDRAW_MS;
    if (!this.dirty && !poseDue) return;
    this.dirty = false;
    this.poseChanged = false;
    this.lastRenderAt = now;
    this.render();
  };

  private render(): void {
    this.upload();
    if (this.fitPending) this.fit();
    this.renderer.render(this.scene, this.camera);
    this.renders++;
    this.drawnPoints = this.geometry.drawRange.count;
    const text = String(this.drawnPoints);
    if (this.container.dataset.points !== text) this.container.dataset.points = text;
  }

  private resize(): void {
    const width = this.container.clientWidth;
    const height = this.container.clientHeight;
    if (width < 2 || height < 2 || (width === this.width && height === this.height)) return;
    this.width = width;
    this.height = height;
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  /**
   * Hands the new part of the cloud to the GPU: the buffers are made anew only when the cloud's
   * arrays grew; otherwise only [uploaded, count) is sent (all colours after a recolour).
   */
  private upload(): void {
    const c = this.cloud;
    const up = this.uploaded;
    if (c.generation !== up.generation) {
      this.geometry.dispose();
      const geometry = new BufferGeometry();
      // The attributes wrap the cloud's own arrays: no copy; the first render sends them whole.
      geometry.setAttribute('position', new BufferAttribute(c.positions, 3).setUsage(DynamicDrawUsage));
      geometry.setAttribute('color', new BufferAttribute(c.colors, 3, true).setUsage(DynamicDrawUsage));
      this.geometry = geometry;
      this.points.geometry = geometry;
    } else {
      const from = c.clears !== up.clears || c.count < up.count ? 0 : up.count;
      const colorsFrom = c.colorVersion !== up.colorVersion ? 0 : from;
      if (c.count > from) this.markRange('position', from, c.count);
      if (c.count > colorsFrom) this.markRange('color', colorsFrom, c.count);
    }
    up.generation = c.generation;
    up.colorVersion = c.colorVersion;
    up.clears = c.clears;
    up.count = c.count;
    this.geometry.setDrawRange(0, c.count);
  }

  private markRange(name: 'position' | 'color', fromPoint: number, toPoint: number): void {
    const attribute = this.geometry.getAttribute(name) as BufferAttribute;
    attribute.clearUpdateRanges();
    attribute.addUpdateRange(fromPoint * 3, (toPoint - fromPoint) * 3);
    attribute.needsUpdate = true;
  }

  /** Frames the cloud, the map and the robot; the camera looks from the south-west, 40 degrees up. */
  private fit(): void {
    this.fitPending = false;
    const box = this.sceneBounds();
    const centre = new Vector3((box.minX + box.maxX) / 2, (box.minY + box.maxY) / 2, (box.minZ + box.maxZ) / 2);
    const radius = 0.5 * Math.hypot(box.maxX - box.minX, box.maxY - box.minY, box.maxZ - box.minZ);
    const distance = Math.max(radius, 1) / Math.tan(((FOV_DEG / 2) * Math.PI) / 180);
    const direction = new Vector3(-0.45, -0.6, 0.66).normalize();
    this.controls.target.copy(centre);
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.near = Math.max(0.02, distance / 1000);
    this.camera.far = Math.max(100, distance * 10);
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.dirty = true;
  }

  private sceneBounds(): Box3 {
    const box: Box3 = { minX: Infinity, minY: Infinity, minZ: 0, maxX: -Infinity, maxY: -Infinity, maxZ: ROBOT_SIZE_M.z };
    const add = (x: number, y: number, z = 0) => {
      box.minX = Math.min(box.minX, x);
      box.maxX = Math.max(box.maxX, x);
      box.minY = Math.min(box.minY, y);
      box.maxY = Math.max(box.maxY, y);
      box.minZ = Math.min(box.minZ, z);
      box.maxZ = Math.max(box.maxZ, z);
    };
    const b = this.cloud.bounds;
    if (this.cloud.count > 0) {
      add(b.minX, b.minY, b.minZ);
      add(b.maxX, b.maxY, b.maxZ);
    }
    if (this.map) for (const [x, y] of mapCorners(this.map)) add(x, y);
    if (this.pose) {
      add(this.pose.x - 2, this.pose.y - 2);
      add(this.pose.x + 2, this.pose.y + 2);
    }
    if (!Number.isFinite(box.minX)) {
      add(-5, -5);
      add(5, 5);
    }
    return box;
  }

  private makeRobot(): Group {
    const { x: sx, y: sy, z: sz } = ROBOT_SIZE_M;
    const box = new BoxGeometry(sx, sy, sz);
    const body = new Mesh(box, new MeshBasicMaterial({ color: 0x38bdf8, transparent: true, opacity: 0.28, depthWrite: false }));
    const edges = new LineSegments(new EdgesGeometry(box), new LineBasicMaterial({ color: 0x7dd3fc }));
    // Heading: an arrow on the top face, centre to the front edge and past it.
    const top = sz / 2 + 0.005;
    const tip = sx * 0.75;
    const arrow = new BufferGeometry();
    arrow.setAttribute(
      'position',
      new BufferAttribute(
        new Float32Array([0, 0, top, tip, 0, top, tip, 0, top, tip - 0.15, 0.1, top, tip, 0, top, tip - 0.15, -0.1, top]),
        3,
      ),
    );
    const heading = new LineSegments(arrow, new LineBasicMaterial({ color: 0xf8fafc }));
    this.robot.add(body, edges, heading);
    return this.robot;
  }

  /** The map as a texture on the floor plane (z = 0), honouring its origin's rotation. */
  private makeFloor(map: MapGrid): Mesh<PlaneGeometry, MeshBasicMaterial> | null {
    const canvas = document.createElement('canvas');
    canvas.width = map.width;
    canvas.height = map.height;
    const ctx = canvas.getContext('2d');
    if (!ctx) return null;
    const image = ctx.createImageData(map.width, map.height);
    paintFloor(map.cells, new Uint32Array(image.data.buffer));
    ctx.putImageData(image, 0, 0);
    const texture = new CanvasTexture(canvas);
    // Canvas row 0 is grid row 0, the bottom of the map: v = 0 must be row 0, so no flip.
    texture.flipY = false;
    texture.magFilter = NearestFilter;
    texture.minFilter = LinearFilter;
    texture.generateMipmaps = false;
    texture.colorSpace = NoColorSpace;
    const widthM = map.width * map.resolution;
    const heightM = map.height * map.resolution;
    const floor = new Mesh(
      new PlaneGeometry(widthM, heightM),
      new MeshBasicMaterial({ map: texture, transparent: true, depthWrite: false }),
    );
    // PlaneGeometry is centred: move its centre to the grid's centre in the map frame.
    const c = Math.cos(map.origin.theta);
    const s = Math.sin(map.origin.theta);
    floor.position.set(map.origin.x + c * widthM / 2 - s * heightM / 2, map.origin.y + s * widthM / 2 + c * heightM / 2, -0.01);
    floor.rotation.set(0, 0, map.origin.theta);
    floor.renderOrder = -1;
    return floor;
  }
}
