import { describe, expect, it } from 'vitest';
import { DEFAULT_TRICYCLE, kinematicsLabel, parseGeometry, robotBody, sameBody, steeringText, tricycleShape, wheelSize } from '../src/tricycle';
import type { Point, TricycleGeometry } from '../src/tricycle';

const GEOMETRY = { wheelbase_m: 0.9, footprint_length_m: 1.3, footprint_width_m: 0.7, footprint_offset_m: 0.45 };
const G: TricycleGeometry = { wheelbase: 0.9, length: 1.3, width: 0.7, offset: 0.45 };

const close = (p: Point, q: Point, digits = 9) => {
  expect(p[0]).toBeCloseTo(q[0], digits);
  expect(p[1]).toBeCloseTo(q[1], digits);
};
const dist = (p: Point, q: Point) => Math.hypot(p[0] - q[0], p[1] - q[1]);

describe('robot body from /robot', () => {
  it('is differential unless the kinematics names a tricycle', () => {
    expect(robotBody({ kinematics: 'differential', geometry: GEOMETRY })).toEqual({ kind: 'differential' });
    expect(robotBody({})).toEqual({ kind: 'differential' });
    expect(robotBody(null)).toEqual({ kind: 'differential' });
    expect(robotBody({ kinematics: 'ackermann' })).toEqual({ kind: 'differential' });
  });

  it('takes a tricycle geometry in metres', () => {
    expect(robotBody({ kinematics: 'tricycle_t1', geometry: GEOMETRY })).toEqual({ kind: 'tricycle', kinematics: 'tricycle_t1', geometry: G, assumed: false });
    const t2 = robotBody({ kinematics: 'tricycle_t2', geometry: GEOMETRY });
    expect(t2.kind === 'tricycle' && t2.kinematics).toBe('tricycle_t2');
    expect(kinematicsLabel(t2)).toBe('tricycle T2');
  });

  it('draws the default tricycle when the geometry is missing or invalid', () => {
    const body = robotBody({ kinematics: 'tricycle_t1' });
    expect(body).toEqual({ kind: 'tricycle', kinematics: 'tricycle_t1', geometry: DEFAULT_TRICYCLE, assumed: true });
    expect(parseGeometry({ ...GEOMETRY, wheelbase_m: 0 })).toBeNull();
    expect(parseGeometry({ ...GEOMETRY, footprint_width_m: 'wide' })).toBeNull();
    expect(parseGeometry({ ...GEOMETRY, footprint_offset_m: undefined })).toEqual({ ...G, offset: 0 });
    expect(parseGeometry({ ...GEOMETRY, footprint_offset_m: -0.1 })).toEqual({ ...G, offset: -0.1 });
  });

  it('compares bodies by what they draw', () => {
    const a = robotBody({ kinematics: 'tricycle_t1', geometry: GEOMETRY });
    expect(sameBody(a, robotBody({ kinematics: 'tricycle_t1', geometry: { ...GEOMETRY } }))).toBe(true);
    expect(sameBody(a, robotBody({ kinematics: 'tricycle_t1', geometry: { ...GEOMETRY, wheelbase_m: 1 } }))).toBe(false);
    expect(sameBody(a, robotBody({ kinematics: 'differential' }))).toBe(false);
    expect(sameBody(robotBody({}), robotBody({ kinematics: 'differential' }))).toBe(true);
  });
});

describe('tricycle shape', () => {
  it('puts the front wheel wheelbase ahead of the rear axle, turned by the steering', () => {
    const pose = { x: 1, y: 2, theta: Math.PI / 2 };
    const shape = tricycleShape(pose, G, 0.3);
    close(shape.rearAxle, [1, 2]);
    close(shape.frontAxle, [1, 2.9]);
    close(shape.frontWheel.center, [1, 2.9]);
    expect(shape.frontWheel.angle).toBeCloseTo(Math.PI / 2 + 0.3);
    // The rear wheels do not steer.
    expect(shape.rearWheels[0].angle).toBeCloseTo(Math.PI / 2);
    expect(shape.rearWheels[1].angle).toBeCloseTo(Math.PI / 2);
  });

  it('sits the rear wheels on the rear axle, left and right, just inside the outline', () => {
    const pose = { x: 0, y: 0, theta: 0 };
    const shape = tricycleShape(pose, G, 0);
    const { width } = wheelSize(G);
    const track = G.width / 2 - width / 2;
    close(shape.rearWheels[0].center, [0, track]); // left
    close(shape.rearWheels[1].center, [0, -track]);
    // Heading pi/2: left is -x.
    const turned = tricycleShape({ x: 0, y: 0, theta: Math.PI / 2 }, G, 0);
    close(turned.rearWheels[0].center, [-track, 0]);
  });

  it('draws the footprint centred footprint_offset ahead of the rear axle', () => {
    const shape = tricycleShape({ x: 0, y: 0, theta: 0 }, G, 0.5);
    // front-left, rear-left, rear-right, front-right
    close(shape.outline[0], [0.45 + 0.65, 0.35]);
    close(shape.outline[1], [0.45 - 0.65, 0.35]);
    close(shape.outline[2], [0.45 - 0.65, -0.35]);
    close(shape.outline[3], [0.45 + 0.65, -0.35]);
    // Rotated and moved with the pose.
    const pose = { x: 3, y: -1, theta: Math.PI };
    const moved = tricycleShape(pose, G, 0);
    close(moved.outline[0], [3 - 1.1, -1 - 0.35]);
  });

  it('turns the front wheel rectangle: its long side along the steered direction', () => {
    const steering = -0.4;
    const shape = tricycleShape({ x: 0, y: 0, theta: 0.2 }, G, steering);
    const [fl, rl, rr, fr] = shape.frontWheel.corners as [Point, Point, Point, Point];
    const along = [fl[0] - rl[0], fl[1] - rl[1]];
    expect(Math.atan2(along[1]!, along[0]!)).toBeCloseTo(0.2 + steering);
    expect(dist(fl, rl)).toBeCloseTo(shape.wheelLength);
    expect(dist(rl, rr)).toBeCloseTo(shape.wheelWidth);
    // Centred on the front axle.
    close([(fl[0] + rr[0]) / 2, (fl[1] + rr[1]) / 2], shape.frontAxle);
    expect(dist(fr, rl)).toBeCloseTo(Math.hypot(shape.wheelLength, shape.wheelWidth));
  });

  it('moves the front wheel with the wheelbase and ignores a non-finite steering', () => {
    const a = tricycleShape({ x: 0, y: 0, theta: 0 }, { ...G, wheelbase: 1.5 }, Number.NaN);
    close(a.frontAxle, [1.5, 0]);
    expect(a.frontWheel.angle).toBe(0);
  });

  it('sizes wheels from the wheelbase within limits', () => {
    expect(wheelSize({ ...G, wheelbase: 0.9 }).length).toBeCloseTo(0.3);
    expect(wheelSize({ ...G, wheelbase: 3 }).length).toBe(0.35);
    expect(wheelSize({ ...G, wheelbase: 0.1 }).length).toBe(0.08);
  });
});

describe('steering text', () => {
  it('says the angle and the side', () => {
    expect(steeringText(0.2)).toBe('11.5° left');
    expect(steeringText(-Math.PI / 6)).toBe('30.0° right');
    expect(steeringText(0)).toBe('0.0°');
    expect(steeringText(-0.0001)).toBe('0.0°');
    expect(steeringText(null)).toBe('–');
    expect(steeringText(Number.NaN)).toBe('–');
  });
});
