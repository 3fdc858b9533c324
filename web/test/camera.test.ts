import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import {
  cameraErrorText,
  DEFAULT_PAN_LIMITS,
  followEventToast,
  headLimits,
  JOG_STEP_RAD,
  jogPanTilt,
  jogsAvailable,
  parseCameraInfo,
  parseFollowDistance,
  parseTarget,
  TARGET_COLORS,
  targetDetail,
  targetOverlay,
} from '../src/camera';

const rad = (d: number) => (d * Math.PI) / 180;
const LIMITS = { pan: [rad(-90), rad(90)] as [number, number], tilt: [rad(-30), rad(20)] as [number, number] };

describe('GET /camera bodies', () => {
  it('parses a pan-tilt camera with its head', () => {
    const body = { kind: 'pan_tilt', width: 640, height: 480, rate_hz: 15, pan: 0.1, tilt: -0.2, pan_limits: [-1.5, 1.5], tilt_limits: [0.3, -0.5] };
    expect(parseCameraInfo(body)).toEqual({ ...body, tilt_limits: [-0.5, 0.3] });
  });

  it('parses fixed and omni cameras, refuses other bodies', () => {
    expect(parseCameraInfo({ kind: 'fixed', width: 320, height: 240, rate_hz: 10 })).toEqual({ kind: 'fixed', width: 320, height: 240, rate_hz: 10 });
    expect(parseCameraInfo({ kind: 'omni', width: 640, height: 640, rate_hz: 5, pan_limits: [1] })?.pan_limits).toBeUndefined();
    expect(parseCameraInfo({ kind: 'zoom' })).toBeNull();
    expect(parseCameraInfo({ error: { code: 'no_camera' } })).toBeNull();
    expect(parseCameraInfo(null)).toBeNull();
  });
});

describe('tracking state and its overlay', () => {
  const box = { x: 100, y: 80, w: 60, h: 40 };

  it('parses the target topic / GET /tracking body', () => {
    expect(parseTarget({ status: 'idle' })).toEqual({ status: 'idle' });
    expect(parseTarget({ status: 'tracking', box, target: { x: 2, y: -0.3 }, range_m: 2.02 })).toEqual({ status: 'tracking', box, target: { x: 2, y: -0.3 }, range_m: 2.02 });
    expect(parseTarget({ status: 'lost', box: { x: 1, y: 2, w: -5, h: 3 } })).toEqual({ status: 'lost' });
    expect(parseTarget({ status: 'searching' })).toBeNull();
    expect(parseTarget('tracking')).toBeNull();
  });

  it('draws tracking solid green, occluded dashed amber, lost dotted red; nothing when idle or without a box', () => {
    const tracking = targetOverlay({ status: 'tracking', box, range_m: 1.5 })!;
    expect(tracking).toEqual({ status: 'tracking', box, color: TARGET_COLORS.tracking, dash: [], label: 'tracking 1.50 m' });
    const occluded = targetOverlay({ status: 'occluded', box })!;
    expect(occluded.color).toBe(TARGET_COLORS.occluded);
    expect(occluded.dash.length).toBe(2);
    expect(occluded.label).toBe('occluded');
    const lost = targetOverlay({ status: 'lost', box })!;
    expect(lost.color).toBe(TARGET_COLORS.lost);
    expect(lost.dash).not.toEqual(occluded.dash);
    expect(targetOverlay({ status: 'idle', box })).toBeNull();
    expect(targetOverlay({ status: 'tracking' })).toBeNull();
    expect(targetOverlay(null)).toBeNull();
    expect(new Set(Object.values(TARGET_COLORS)).size).toBe(4);
  });

  it('describes the target beside the badge', () => {
    expect(targetDetail({ status: 'tracking', box, target: { x: 2, y: 0.25 }, range_m: 2.02 })).toBe('2.02 m · at (2.00, 0.25) · box 60×40 px');
    expect(targetDetail({ status: 'idle' })).toBe('draw a box on the image');
  });
});

describe('pan/tilt jogs', () => {
  it('steps 5 degrees: left and up are positive', () => {
    expect(JOG_STEP_RAD).toBeCloseTo(rad(5));
    const at = { pan: 0.2, tilt: -0.1 };
    expect(jogPanTilt(at, 'left', LIMITS).pan).toBeCloseTo(0.2 + rad(5));
    expect(jogPanTilt(at, 'right', LIMITS).pan).toBeCloseTo(0.2 - rad(5));
    expect(jogPanTilt(at, 'up', LIMITS)).toEqual({ pan: 0.2, tilt: -0.1 + rad(5) });
    expect(jogPanTilt(at, 'down', LIMITS).tilt).toBeCloseTo(-0.1 - rad(5));
    expect(jogPanTilt(at, 'center', LIMITS)).toEqual({ pan: 0, tilt: 0 });
  });

  it('clamps to the head limits', () => {
    expect(jogPanTilt({ pan: rad(88), tilt: 0 }, 'left', LIMITS).pan).toBeCloseTo(rad(90));
    expect(jogPanTilt({ pan: rad(90), tilt: 0 }, 'left', LIMITS).pan).toBeCloseTo(rad(90));
    expect(jogPanTilt({ pan: rad(-89), tilt: 0 }, 'right', LIMITS).pan).toBeCloseTo(rad(-90));
    expect(jogPanTilt({ pan: 0, tilt: rad(18) }, 'up', LIMITS).tilt).toBeCloseTo(rad(20));
    expect(jogPanTilt({ pan: 0, tilt: rad(-28) }, 'down', LIMITS).tilt).toBeCloseTo(rad(-30));
    // A head reported outside its limits comes back inside with any jog.
    expect(jogPanTilt({ pan: 2, tilt: -1 }, 'up', LIMITS)).toEqual({ pan: rad(90), tilt: rad(-30) });
    // A range that excludes 0: centre is the nearest end.
    expect(jogPanTilt({ pan: 0.5, tilt: 0.4 }, 'center', { pan: [0.2, 1], tilt: [0.3, 0.6] })).toEqual({ pan: 0.2, tilt: 0.3 });
  });

  it('uses default limits when the server gives none', () => {
    expect(headLimits({}).pan).toEqual(DEFAULT_PAN_LIMITS);
    expect(jogPanTilt({ pan: Math.PI - 0.01, tilt: 0 }, 'left', {}).pan).toBeCloseTo(Math.PI);
    expect(jogPanTilt({ pan: Number.NaN, tilt: 0 }, 'left', {}).pan).toBeCloseTo(rad(5));
  });

  it('disables jogs that would not move the head', () => {
    expect(jogsAvailable({ pan: rad(90), tilt: 0 }, LIMITS)).toEqual({ left: false, right: true, up: true, down: true, center: true });
    expect(jogsAvailable({ pan: 0, tilt: rad(-30) }, LIMITS)).toEqual({ left: true, right: true, up: true, down: false, center: true });
    expect(jogsAvailable({ pan: 0, tilt: 0 }, LIMITS).center).toBe(false);
  });
});

describe('following', () => {
  it('takes a distance of 0.5..5 m', () => {
    expect(parseFollowDistance('1.5')).toEqual({ distance: 1.5 });
    expect(parseFollowDistance(' 0.5 ')).toEqual({ distance: 0.5 });
    expect(parseFollowDistance('5')).toEqual({ distance: 5 });
    expect(parseFollowDistance('0.4')).toHaveProperty('problem');
    expect(parseFollowDistance('6')).toHaveProperty('problem');
    expect(parseFollowDistance('')).toHaveProperty('problem');
    expect(parseFollowDistance('far')).toHaveProperty('problem');
  });

  it('words the follow event as a toast', () => {
    expect(followEventToast({ reason: 'target_lost' })).toEqual({ text: 'following ended: target lost', kind: 'error' });
    expect(followEventToast({ reason: 'teleop' })).toEqual({ text: 'following ended: teleop took over', kind: 'error' });
    expect(followEventToast({ reason: 'estop' })?.text).toBe('following ended: e-stop engaged');
    expect(followEventToast({ reason: 'canceled' })).toEqual({ text: 'following ended: canceled', kind: 'info' });
    expect(followEventToast({ reason: 'battery_low' })?.text).toBe('following ended: battery low');
    expect(followEventToast({ action: 'start', distance_m: 1.5 })).toBeNull();
    expect(followEventToast(null)).toBeNull();
  });

  it('explains refusals with the server code', () => {
    expect(cameraErrorText(new ApiError(409, 'not_tracking', 'no target'))).toMatch(/draw a box.*\(not_tracking\)$/);
    expect(cameraErrorText(new ApiError(403, 'forbidden', 'operator role needed'))).toMatch(/operator role.*\(forbidden\)/);
    expect(cameraErrorText(new ApiError(400, 'invalid_field', 'box.w must be >= 8'))).toBe('box.w must be >= 8 (invalid_field)');
    expect(cameraErrorText(new ApiError(404, 'not_found', 'no such path'))).toMatch(/no camera tracking/);
    expect(cameraErrorText(new Error('boom'))).toBe('boom');
  });
});
