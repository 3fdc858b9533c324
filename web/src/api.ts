// REST client of mobotd (/api/v1). Every call carries the bearer token; errors come back as
// ApiError with the server's {"error":{"code","message"}}.

import { ApiError, errorText } from './apierror';
import type { ImageBox } from './camera_box';
import type { Goal } from './goals';
import type { JsonObstacleMap } from './ipabd';
import type { EstimatorName } from './localization';
import type { MappingStartReply, MappingStatus, MappingStopReply } from './mapping';
import type { OperatorAction } from './operator';
import type { SweepInfo, SweepRequest } from './sweeps';
import type { JsonGeometry } from './tricycle';
import type { ZoneRequest } from './zones';

export interface Pose {
  x: number;
  y: number;
  theta: number;
}

export interface SensorHealth {
  ok: boolean;
  rate_hz: number;
  /** Only when not ok: `stale`, or the driver's word on its device (`missing`, `silent`, `checksum`, ...). */
  reason?: string;
}

export interface RobotStatus {
  t: number;
  mode: string;
  pose: Pose;
  velocity: { v: number; w: number };
  /** `method` starts with ekf, particle_filter, slam or odometry, a detail in parentheses may follow. */
  localization: { method: string; cov: number[]; converged?: boolean };
  /** `differential`, `tricycle_t1` or `tricycle_t2`. */
  kinematics: string;
  /** Tricycles: the front wheel's angle (rad, CCW). */
  steering_rad?: number;
  /** Tricycles: wheelbase and footprint (m); the footprint's centre is footprint_offset_m ahead of the rear axle. */
  geometry?: JsonGeometry;
  estop: boolean;
  sensors: Record<string, SensorHealth>;
}

export interface GoalRequest {
  x: number;
  y: number;
  theta?: number;
  planner?: string;
  controller?: string;
}

export interface SimTruth {
  t: number;
  pose: Pose;
  collisions: number;
}

export interface MapInfo {
  id: number;
  name: string;
  width: number;
  height: number;
  resolution: number;
  origin: Pose;
  created: number;
  active: boolean;
}

export interface RunInfo {
  id: number;
  name: string;
  started: number;
  ended?: number;
  distance_m: number;
  goals: { succeeded: number; failed: number; canceled: number };
}

export interface TrajectoryPoint {
  t: number;
  x: number;
  y: number;
  theta: number;
}

export interface RunEvent {
  t: number;
  kind: string;
  detail: unknown;
}

export interface Health {
  status: string;
  version: string;
  backend: string;
  uptime_s: number;
}

export interface MapImport {
  name: string;
  resolution: number;
  origin: Pose;
  image_base64: string;
  negate?: boolean;
  occupied_thresh?: number;
  free_thresh?: number;
}

/** Turns a non-2xx response into an ApiError, reading the {"error":{...}} body when there is one. */
export async function errorFromResponse(response: Response): Promise<ApiError> {
  let code = `http_${response.status}`;
  let message = `${response.status} ${response.statusText || 'error'}`.trim();
  try {
    const text = await response.text();
    const body = JSON.parse(text) as { error?: { code?: string; message?: string } };
    if (body.error) {
      code = body.error.code ?? code;
      message = body.error.message ?? message;
    }
  } catch {
    // not JSON: keep the status line
  }
  return new ApiError(response.status, code, message);
}

/** Whether the server serves a path: a wrong method on a known path is 405, an unknown path 404 (both before auth). */
export type PathPresence = 'present' | 'absent' | 'unknown';

/** Told of every answered request: the operator lock learns from driving commands and their refusals. */
export type ResponseObserver = (method: string, path: string, error: ApiError | null) => void;

export class ApiClient {
  /** Called after each request the server answered (not for unreachable servers). */
  onResponse: ResponseObserver | null = null;

  constructor(
    private token: string,
    private readonly base = '',
  ) {}

  setToken(token: string): void {
    this.token = token;
  }

  private async request(method: string, path: string, body?: unknown): Promise<Response> {
    const headers: Record<string, string> = { Authorization: `Bearer ${this.token}` };
    let payload: string | undefined;
    if (body !== undefined) {
      headers['Content-Type'] = 'application/json';
      payload = JSON.stringify(body);
    }
    let response: Response;
    try {
      response = await fetch(`${this.base}${path}`, { method, headers, body: payload, cache: 'no-store' });
    } catch (error) {
      throw new ApiError(0, 'network_error', `server unreachable (${errorText(error)})`);
    }
    if (!response.ok) {
      const error = await errorFromResponse(response);
      this.onResponse?.(method, path, error);
      throw error;
    }
    this.onResponse?.(method, path, null);
    return response;
  }

  private async json<T>(method: string, path: string, body?: unknown): Promise<T> {
    const response = await this.request(method, path, body);
    if (response.status === 204) return undefined as T;
    // A 200 with an empty body (a DELETE that says nothing) is no body, not a parse error.
    const text = await response.text();
    return (text.trim() === '' ? undefined : JSON.parse(text)) as T;
  }

  /** GET returning the raw body (for downloads that need the bearer header). */
  async blob(path: string): Promise<Blob> {
    return (await this.request('GET', path)).blob();
  }

  /** GET returning the raw bytes (binary cloud frames). */
  async bytes(path: string): Promise<ArrayBuffer> {
    return (await this.request('GET', path)).arrayBuffer();
  }

  /**
   * Asks with GET whether `path` exists, without doing what another method would do there: 404
   * not_found is absent; 2xx, 401, 403 and 405 are present; anything else (unreachable) unknown.
   */
  async probe(path: string): Promise<PathPresence> {
    try {
      await this.request('GET', path);
      return 'present';
    } catch (error) {
      if (!(error instanceof ApiError)) return 'unknown';
      if (error.status === 404 && error.code === 'not_found') return 'absent';
      if (error.status === 401 || error.status === 403 || error.status === 405) return 'present';
      return 'unknown';
    }
  }

  /** This token: its id, label, role and expiry (parsed by login.ts). */
  whoami(): Promise<unknown> {
    return this.json('GET', '/api/v1/whoami');
  }

  health(): Promise<Health> {
    return this.json('GET', '/api/v1/health');
  }
  robot(): Promise<RobotStatus> {
    return this.json('GET', '/api/v1/robot');
  }
  estop(engaged: boolean): Promise<{ estop: boolean }> {
    return this.json('POST', '/api/v1/estop', { engaged });
  }
  teleop(v: number, w: number, ttlMs = 300): Promise<{ v: number; w: number }> {
    return this.json('POST', '/api/v1/teleop', { v, w, ttl_ms: ttlMs });
  }
  maps(): Promise<MapInfo[]> {
    return this.json('GET', '/api/v1/maps');
  }
  importMap(body: MapImport): Promise<{ id: number }> {
    return this.json('POST', '/api/v1/maps', body);
  }
  activateMap(id: number): Promise<MapInfo> {
    return this.json('POST', `/api/v1/maps/${id}/activate`);
  }
  deleteMap(id: number): Promise<void> {
    return this.json('DELETE', `/api/v1/maps/${id}`);
  }
  runs(): Promise<RunInfo[]> {
    return this.json('GET', '/api/v1/runs');
  }
  trajectory(id: number): Promise<TrajectoryPoint[]> {
    return this.json('GET', `/api/v1/runs/${id}/trajectory?format=json`);
  }
  runEvents(id: number): Promise<RunEvent[]> {
    return this.json('GET', `/api/v1/runs/${id}/events`);
  }
  goals(): Promise<Goal[]> {
    return this.json('GET', '/api/v1/goals');
  }
  submitGoal(body: GoalRequest): Promise<Goal> {
    return this.json('POST', '/api/v1/goals', body);
  }
  cancelGoal(id: number): Promise<Goal> {
    return this.json('DELETE', `/api/v1/goals/${id}`);
  }
  setLocalizationPose(pose: Pose, cov?: number[]): Promise<unknown> {
    return this.json('POST', '/api/v1/localization/pose', cov ? { ...pose, cov } : pose);
  }
  localizeGlobally(): Promise<{ method: string }> {
    return this.json('POST', '/api/v1/localization/global', {});
  }
  setLocalizationMethod(method: EstimatorName): Promise<{ method: string }> {
    return this.json('PUT', '/api/v1/localization/method', { method });
  }
  mapping(): Promise<MappingStatus> {
    return this.json('GET', '/api/v1/mapping');
  }
  startMapping(): Promise<MappingStartReply> {
    return this.json('POST', '/api/v1/mapping', { action: 'start' });
  }
  /** Stops mapping: with a name the map is stored and made active, without one it is discarded. */
  stopMapping(saveAs?: string): Promise<MappingStopReply> {
    return this.json('POST', '/api/v1/mapping', saveAs === undefined ? { action: 'stop' } : { action: 'stop', save_as: saveAs });
  }
  zones(mapId: number): Promise<unknown> {
    return this.json('GET', `/api/v1/maps/${mapId}/zones`);
  }
  addZone(mapId: number, body: ZoneRequest): Promise<{ id: number }> {
    return this.json('POST', `/api/v1/maps/${mapId}/zones`, body);
  }
  deleteZone(mapId: number, zoneId: number): Promise<void> {
    return this.json('DELETE', `/api/v1/maps/${mapId}/zones/${zoneId}`);
  }
  sweeps(): Promise<SweepInfo[]> {
    return this.json('GET', '/api/v1/sweeps');
  }
  sweep(id: number): Promise<SweepInfo> {
    return this.json('GET', `/api/v1/sweeps/${id}`);
  }
  startSweep(body: SweepRequest): Promise<SweepInfo> {
    return this.json('POST', '/api/v1/sweeps', body);
  }
  /** The whole cloud as one binary `cloud` frame (409 sweep_not_done until the sweep is done). */
  sweepCloudFrame(id: number): Promise<ArrayBuffer> {
    return this.bytes(`/api/v1/sweeps/${id}/cloud?format=bin`);
  }
  sweepObstacleMap(id: number): Promise<JsonObstacleMap> {
    return this.json('GET', `/api/v1/sweeps/${id}/obstacle_map`);
  }
  /** GET /api/v1/camera: the camera's kind, image size, rate and head (404 no_camera without one). */
  camera(): Promise<unknown> {
    return this.json('GET', '/api/v1/camera');
  }
  /** PUT /api/v1/camera/pan_tilt (rad, within the head's limits). */
  setPanTilt(pan: number, tilt: number): Promise<unknown> {
    return this.json('PUT', '/api/v1/camera/pan_tilt', { pan, tilt });
  }
  /** GET /api/v1/tracking: the tracked target. */
  tracking(): Promise<unknown> {
    return this.json('GET', '/api/v1/tracking');
  }
  /** POST /api/v1/tracking: start tracking what is inside the box (image pixels). */
  startTracking(box: ImageBox): Promise<unknown> {
    return this.json('POST', '/api/v1/tracking', { box: { x: box.x, y: box.y, w: box.w, h: box.h } });
  }
  stopTracking(): Promise<unknown> {
    return this.json('DELETE', '/api/v1/tracking');
  }
  /** POST /api/v1/follow: follow the tracked target at distance_m (0.5..5). */
  follow(distance: number): Promise<unknown> {
    return this.json('POST', '/api/v1/follow', { distance_m: distance });
  }
  stopFollowing(): Promise<unknown> {
    return this.json('DELETE', '/api/v1/follow');
  }
  /** GET /api/v1/operator: who holds the operator lock ({holder: null} when nobody). */
  operator(): Promise<unknown> {
    return this.json('GET', '/api/v1/operator');
  }
  /** POST /api/v1/operator: the lock after the change (take_over: admin only). */
  operatorAction(action: OperatorAction): Promise<unknown> {
    return this.json('POST', '/api/v1/operator', { action });
  }
  /** GET /api/v1/clients: every open connection (admin only, 403 otherwise). */
  clients(): Promise<unknown> {
    return this.json('GET', '/api/v1/clients');
  }
  simTruth(): Promise<SimTruth> {
    return this.json('GET', '/api/v1/sim/truth');
  }
  addObstacle(body: { x: number; y: number; radius: number; height?: number }): Promise<{ id: number }> {
    return this.json('POST', '/api/v1/sim/obstacles', body);
  }
  removeObstacle(id: number): Promise<void> {
    return this.json('DELETE', `/api/v1/sim/obstacles/${id}`);
  }
}
