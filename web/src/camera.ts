// The camera, target tracking and following, as the Live page's Camera card shows them: the body of
// GET /api/v1/camera, the tracked target (GET /api/v1/tracking and the `target` topic) and how its
// window is drawn over the image, pan/tilt jogs clamped to the head's limits, the following
// distance, and the words for the server's refusals and for the `follow` event. Pure (no DOM, no
// fetch), unit-tested; camera_panel.ts renders it.

import { ApiError, errorText } from './apierror';
import type { ImageBox } from './camera_box';
import { fmt } from './ui';

export type CameraKind = 'pan_tilt' | 'omni' | 'fixed';

/** GET /api/v1/camera (angles in radians). */
export interface CameraInfo {
  kind: CameraKind;
  width: number;
  height: number;
  rate_hz: number;
  pan?: number;
  tilt?: number;
  pan_limits?: [number, number];
  tilt_limits?: [number, number];
}

const finite = (x: unknown): x is number => typeof x === 'number' && Number.isFinite(x);

function limits(value: unknown): [number, number] | undefined {
  if (!Array.isArray(value) || value.length !== 2 || !finite(value[0]) || !finite(value[1])) return undefined;
  return value[0] <= value[1] ? [value[0], value[1]] : [value[1], value[0]];
}

/** Validates a GET /camera body; null when it is not one. */
export function parseCameraInfo(value: unknown): CameraInfo | null {
  if (!value || typeof value !== 'object') return null;
  const v = value as Record<string, unknown>;
  if (v.kind !== 'pan_tilt' && v.kind !== 'omni' && v.kind !== 'fixed') return null;
  const info: CameraInfo = {
    kind: v.kind,
    width: finite(v.width) && v.width > 0 ? v.width : 0,
    height: finite(v.height) && v.height > 0 ? v.height : 0,
    rate_hz: finite(v.rate_hz) ? v.rate_hz : 0,
  };
  if (finite(v.pan)) info.pan = v.pan;
  if (finite(v.tilt)) info.tilt = v.tilt;
  const pan = limits(v.pan_limits);
  const tilt = limits(v.tilt_limits);
  if (pan) info.pan_limits = pan;
  if (tilt) info.tilt_limits = tilt;
  return info;
}

// ---- tracking ----

export type TrackStatus = 'idle' | 'tracking' | 'occluded' | 'lost';

/** GET /api/v1/tracking and the `target` topic: the box in image pixels, the target in the robot frame (m). */
export interface TargetState {
  status: TrackStatus;
  box?: ImageBox;
  target?: { x: number; y: number };
  range_m?: number;
}

export const IDLE_TARGET: TargetState = { status: 'idle' };

function parseBox(value: unknown): ImageBox | undefined {
  if (!value || typeof value !== 'object') return undefined;
  const b = value as Record<string, unknown>;
  if (!finite(b.x) || !finite(b.y) || !finite(b.w) || !finite(b.h) || b.w < 0 || b.h < 0) return undefined;
  return { x: b.x, y: b.y, w: b.w, h: b.h };
}

/** Validates a tracking body; null when it is not one. */
export function parseTarget(value: unknown): TargetState | null {
  if (!value || typeof value !== 'object') return null;
  const v = value as Record<string, unknown>;
  if (v.status !== 'idle' && v.status !== 'tracking' && v.status !== 'occluded' && v.status !== 'lost') return null;
  const state: TargetState = { status: v.status };
  const box = parseBox(v.box);
  if (box) state.box = box;
  const t = v.target as Record<string, unknown> | undefined;
  if (t && typeof t === 'object' && finite(t.x) && finite(t.y)) state.target = { x: t.x, y: t.y };
  if (finite(v.range_m)) state.range_m = v.range_m;
  return state;
}

/** Colour of each tracking status (overlay, badge). */
export const TARGET_COLORS: Record<TrackStatus, string> = {
  idle: '#94a3b8',
  tracking: '#34d399',
  occluded: '#fbbf24',
  lost: '#f87171',
};

/** How the tracked window is drawn over the image. */
export interface TargetOverlay {
  status: TrackStatus;
  box: ImageBox;
  color: string;
  /** Canvas line dash in CSS pixels; empty: solid. */
  dash: number[];
  /** Text drawn above the box. */
  label: string;
}

/**
 * The overlay for a tracking state: a solid green box while tracking, a dashed amber one where the
 * target was last seen while occluded, a dashed red one once lost; nothing when idle or without a
 * box.
 */
export function targetOverlay(state: TargetState | null): TargetOverlay | null {
  if (!state || state.status === 'idle' || !state.box) return null;
  const range = state.range_m !== undefined ? ` ${fmt(state.range_m)} m` : '';
  return {
    status: state.status,
    box: state.box,
    color: TARGET_COLORS[state.status],
    dash: state.status === 'tracking' ? [] : state.status === 'occluded' ? [6, 4] : [2, 4],
    label: `${state.status}${range}`,
  };
}

/** The card's line beside the status badge: range and where the target is (robot frame). */
export function targetDetail(state: TargetState | null): string {
  if (!state || state.status === 'idle') return 'draw a box on the image';
  const parts: string[] = [];
  if (state.range_m !== undefined) parts.push(`${fmt(state.range_m)} m`);
  if (state.target) parts.push(`at (${fmt(state.target.x)}, ${fmt(state.target.y)})`);
  if (state.box) parts.push(`box ${Math.round(state.box.w)}×${Math.round(state.box.h)} px`);
  return parts.join(' · ');
}

// ---- pan / tilt ----

export const JOG_STEP_RAD = (5 * Math.PI) / 180;
/** Without limits from the server a head turns at most this far. */
export const DEFAULT_PAN_LIMITS: [number, number] = [-Math.PI, Math.PI];
export const DEFAULT_TILT_LIMITS: [number, number] = [-Math.PI / 2, Math.PI / 2];

export type JogDirection = 'left' | 'right' | 'up' | 'down' | 'center';
export const JOG_DIRECTIONS: readonly JogDirection[] = ['left', 'right', 'up', 'down', 'center'];

export interface PanTilt {
  pan: number;
  tilt: number;
}

export interface PanTiltLimits {
  pan?: [number, number];
  tilt?: [number, number];
}

const clamp = (x: number, [lo, hi]: [number, number]) => Math.min(hi, Math.max(lo, x));

/** The head's limits, the defaults where the server gave none. */
export function headLimits(info: Pick<CameraInfo, 'pan_limits' | 'tilt_limits'>): Required<PanTiltLimits> {
  return { pan: info.pan_limits ?? DEFAULT_PAN_LIMITS, tilt: info.tilt_limits ?? DEFAULT_TILT_LIMITS };
}

/**
 * The pan/tilt after one jog: pan positive turns left (counter-clockwise), tilt positive looks up;
 * `center` is (0, 0). Always within the limits (0 itself clamped when a range excludes it).
 */
export function jogPanTilt(current: PanTilt, direction: JogDirection, limits: PanTiltLimits, step = JOG_STEP_RAD): PanTilt {
  const pan = limits.pan ?? DEFAULT_PAN_LIMITS;
  const tilt = limits.tilt ?? DEFAULT_TILT_LIMITS;
  const p = finite(current.pan) ? current.pan : 0;
  const t = finite(current.tilt) ? current.tilt : 0;
  switch (direction) {
    case 'left':
      return { pan: clamp(p + step, pan), tilt: clamp(t, tilt) };
    case 'right':
      return { pan: clamp(p - step, pan), tilt: clamp(t, tilt) };
    case 'up':
      return { pan: clamp(p, pan), tilt: clamp(t + step, tilt) };
    case 'down':
      return { pan: clamp(p, pan), tilt: clamp(t - step, tilt) };
    case 'center':
      return { pan: clamp(0, pan), tilt: clamp(0, tilt) };
  }
}

/** Which jogs would move the head (a button at its limit is disabled). */
export function jogsAvailable(current: PanTilt, limits: PanTiltLimits): Record<JogDirection, boolean> {
  const moves = (d: JogDirection) => {
    const next = jogPanTilt(current, d, limits);
    return Math.abs(next.pan - current.pan) > 1e-6 || Math.abs(next.tilt - current.tilt) > 1e-6;
  };
  return { left: moves('left'), right: moves('right'), up: moves('up'), down: moves('down'), center: moves('center') };
}

// ---- following ----

export const FOLLOW_MIN_M = 0.5;
export const FOLLOW_MAX_M = 5;
export const FOLLOW_DEFAULT_M = 1.5;

/** The distance field's text -> metres, or why it cannot be sent. */
export function parseFollowDistance(text: string): { distance: number } | { problem: string } {
  const trimmed = text.trim();
  const value = Number(trimmed);
  if (trimmed === '' || !Number.isFinite(value)) return { problem: `Enter a following distance in metres (${FOLLOW_MIN_M}…${FOLLOW_MAX_M}).` };
  if (value < FOLLOW_MIN_M || value > FOLLOW_MAX_M) return { problem: `The following distance must be ${FOLLOW_MIN_M}…${FOLLOW_MAX_M} m (not ${trimmed}).` };
  return { distance: value };
}

/** Reasons of a `follow` event that mean the user ended it: shown as information, not an error. */
const REQUESTED_ENDS = new Set(['canceled', 'cancelled', 'stopped', 'requested', 'delete', 'user']);

const REASON_TEXT: Record<string, string> = {
  target_lost: 'target lost',
  lost: 'target lost',
  teleop: 'teleop took over',
  teleop_override: 'teleop took over',
  estop: 'e-stop engaged',
  tracking_stopped: 'tracking stopped',
};

/** The toast for a `follow` event; null for one without a reason (following started). */
export function followEventToast(detail: unknown): { text: string; kind: 'info' | 'error' } | null {
  if (!detail || typeof detail !== 'object') return null;
  const reason = (detail as { reason?: unknown }).reason;
  if (typeof reason !== 'string' || reason === '') return null;
  const words = REASON_TEXT[reason] ?? reason.replace(/_/g, ' ');
  return { text: `following ended: ${words}`, kind: REQUESTED_ENDS.has(reason) ? 'info' : 'error' };
}

// ---- refusals ----

const ERROR_TEXT: Record<string, string> = {
  not_tracking: 'No target is tracked: draw a box around it on the camera image first.',
  no_camera: 'This robot has no camera.',
  no_pan_tilt: 'This camera cannot pan or tilt.',
  estop_engaged: 'The e-stop is engaged: release it first.',
  forbidden: 'This token may not do that (the operator role is needed).',
  not_following: 'The robot is not following.',
  operator_busy: 'Another operator holds the robot.',
};

/** The message shown for a refused camera, tracking or follow request: our words, then the server's and its code. */
export function cameraErrorText(error: unknown): string {
  if (error instanceof ApiError) {
    const ours = ERROR_TEXT[error.code];
    if (error.status === 404 && error.code === 'not_found') return 'This server has no camera tracking (404 not_found).';
    if (ours) return `${ours} (${error.code})`;
    return `${error.describe()}`;
  }
  return errorText(error);
}
