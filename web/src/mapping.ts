// Mapping (SLAM) from the dashboard: the REST bodies of /api/v1/mapping, the map name rule, and
// the state of the mapping panel: what the server says (GET /mapping, the robot's mode, `mapping`
// events), what this page asked for (start, stop and save, discard) and so which controls are
// enabled. Pure (no DOM, no fetch), unit-tested; mapping_panel.ts renders it.

import { ApiError, errorText } from './apierror';

/** GET /api/v1/mapping. */
export interface MappingStatus {
  mapping: boolean;
  scans: number;
  nodes: number;
  loop_closures: number;
  /** Robot clock (s) when mapping started; present while mapping. */
  started_t?: number;
}

/** POST /api/v1/mapping replies. */
export interface MappingStartReply {
  mapping: boolean;
}
export interface MappingStopReply {
  mapping: boolean;
  map_id?: number;
}

/**
 * unknown: not asked yet; unsupported: the server has no /mapping (404); idle / mapping: as the
 * server says; starting, saving, discarding: a request of this page is under way.
 */
export type MappingPhase = 'unknown' | 'unsupported' | 'idle' | 'starting' | 'mapping' | 'saving' | 'discarding';

export type MappingRequest = 'start' | 'save' | 'discard';

export interface MappingControls {
  start: boolean;
  save: boolean;
  discard: boolean;
  /** The map name field. */
  name: boolean;
  /** A request is under way. */
  busy: boolean;
}

/** A map name as the server stores names (1..128 characters, as for imports). */
export const MAX_MAP_NAME = 128;

/** Why `name` cannot name a saved map, or null when it can. */
export function validateMapName(name: string): string | null {
  const trimmed = name.trim();
  if (trimmed.length === 0) return 'Enter a name for the map: Stop & save stores it under that name.';
  if (trimmed.length > MAX_MAP_NAME) return `The name is ${trimmed.length} characters long; at most ${MAX_MAP_NAME}.`;
  return null;
}

/** Validates a GET /mapping body; null when it is not one. */
export function parseMappingStatus(value: unknown): MappingStatus | null {
  if (!value || typeof value !== 'object') return null;
  const v = value as Record<string, unknown>;
  if (typeof v.mapping !== 'boolean') return null;
  const num = (x: unknown) => (typeof x === 'number' && Number.isFinite(x) ? x : 0);
  const status: MappingStatus = { mapping: v.mapping, scans: num(v.scans), nodes: num(v.nodes), loop_closures: num(v.loop_closures) };
  if (typeof v.started_t === 'number' && Number.isFinite(v.started_t)) status.started_t = v.started_t;
  return status;
}

/** The message shown for a refused mapping request. */
export function mappingErrorText(error: unknown): string {
  if (error instanceof ApiError) {
    switch (error.code) {
      case 'mapping_active':
        return 'Mapping is already running (started elsewhere): the panel follows it.';
      case 'not_mapping':
        return 'Mapping is not running (it was stopped elsewhere).';
      case 'forbidden':
        return 'This token may not map (the operator role is needed).';
      case 'estop_engaged':
        return 'The e-stop is engaged: release it first.';
      default:
        if (error.status === 404 && error.code === 'not_found') return 'This server cannot build maps (no /api/v1/mapping).';
        return error.describe();
    }
  }
  return errorText(error);
}

export class MappingState {
  phase: MappingPhase = 'unknown';
  status: MappingStatus | null = null;
  /** The last refusal (shown until the next request or a dismissal). */
  error: string | null = null;
  /** The map the last Stop & save stored. */
  saved: { id: number; name: string } | null = null;
  /** Bumped on every change; the panel re-renders when it moved. */
  version = 0;
  private pending: MappingRequest | null = null;

  get mapping(): boolean {
    return this.phase === 'mapping' || this.phase === 'saving' || this.phase === 'discarding';
  }

  get busy(): boolean {
    return this.pending !== null;
  }

  /** A GET /mapping reply. While a request of ours is under way its reply decides, not a poll. */
  onStatus(status: MappingStatus): void {
    this.status = status;
    if (!this.pending) this.phase = status.mapping ? 'mapping' : 'idle';
    this.version++;
  }

  /** GET /mapping answered 404 not_found: no mapping on this server. */
  onUnsupported(): void {
    this.phase = 'unsupported';
    this.status = null;
    this.pending = null;
    this.version++;
  }

  /** The robot's mode (status topic): true when it disagrees with the phase, so GET /mapping should be asked. */
  modeDisagrees(mode: string): boolean {
    if (this.phase === 'unsupported' || this.pending) return false;
    return (mode === 'mapping') !== (this.phase === 'mapping');
  }

  /** Whether `request` may be sent now; the reason shown when not. */
  refusal(request: MappingRequest, name = ''): string | null {
    if (this.phase === 'unsupported') return 'This server cannot build maps.';
    if (this.pending) return 'A mapping request is under way.';
    if (request === 'start') return this.phase === 'mapping' ? 'Mapping is already running.' : null;
    if (this.phase !== 'mapping') return 'Mapping is not running.';
    return request === 'save' ? validateMapName(name) : null;
  }

  /** The request was sent. */
  begin(request: MappingRequest): void {
    this.pending = request;
    this.error = null;
    this.phase = request === 'start' ? 'starting' : request === 'save' ? 'saving' : 'discarding';
    this.version++;
  }

  /** The server accepted the request. */
  succeeded(request: MappingRequest, reply: { mapping?: boolean; map_id?: number } = {}, name = ''): void {
    this.pending = null;
    if (request === 'start') {
      this.phase = 'mapping';
      this.saved = null;
      this.status = { mapping: true, scans: 0, nodes: 0, loop_closures: 0, ...(this.status?.mapping ? this.status : {}) };
    } else {
      this.phase = 'idle';
      if (this.status) this.status = { ...this.status, mapping: false };
      if (request === 'save' && typeof reply.map_id === 'number') this.saved = { id: reply.map_id, name: name.trim() };
    }
    this.version++;
  }

  /** The server refused the request: the phase follows what the refusal says about the server. */
  failed(request: MappingRequest, error: unknown): void {
    this.pending = null;
    this.error = mappingErrorText(error);
    const code = error instanceof ApiError ? error.code : '';
    if (error instanceof ApiError && error.status === 404 && code === 'not_found') this.phase = 'unsupported';
    else if (code === 'mapping_active') this.phase = 'mapping';
    else if (code === 'not_mapping') this.phase = 'idle';
    else this.phase = request === 'start' ? 'idle' : 'mapping';
    this.version++;
  }

  /** A refusal of the page itself (an empty name): shown like the server's. */
  showError(message: string | null): void {
    this.error = message;
    this.version++;
  }

  controls(): MappingControls {
    const busy = this.pending !== null;
    const mapping = this.phase === 'mapping';
    return {
      start: !busy && (this.phase === 'idle' || this.phase === 'unknown'),
      save: !busy && mapping,
      discard: !busy && mapping,
      name: !busy && mapping,
      busy,
    };
  }

  /** Seconds since mapping started on the robot clock, or null. */
  elapsed(clock: number | null): number | null {
    const started = this.status?.started_t;
    if (!this.mapping || started === undefined || clock === null) return null;
    return Math.max(0, clock - started);
  }

  /** "scans 120 · nodes 14 · loop closures 2", or null without a status. */
  summary(): string | null {
    const s = this.status;
    if (!s) return null;
    return `scans ${s.scans} · nodes ${s.nodes} · loop closures ${s.loop_closures}`;
  }
}
