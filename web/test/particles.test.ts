import { describe, expect, it } from 'vitest';
import { decodeBinaryFrame, FrameError } from '../src/frames';
import { decodeParticlesBody, MIN_PARTICLE_ALPHA, particleAlphas, particlesFromJson, weightedMean } from '../src/particles';
import { frame, particlesBody } from './frame_bytes';

describe('particles frames (topic 6)', () => {
  it('decode count, total and x, y, theta, weight per particle', () => {
    const f = decodeBinaryFrame(frame(6, particlesBody([[1, 2, 0.5, 0.75], [-3, 4, -1, 0.25]], { total: 5000 }), { seq: 12, t: 8 }));
    expect(f.kind).toBe('particles');
    if (f.kind !== 'particles') return;
    expect(f.header).toMatchObject({ topic: 'particles', seq: 12, t: 8 });
    const p = f.particles;
    expect([p.count, p.total]).toEqual([2, 5000]);
    expect([...p.data]).toEqual([1, 2, 0.5, 0.75, -3, 4, -1, 0.25]);
  });

  it('honour a longer header', () => {
    const f = decodeBinaryFrame(frame(6, particlesBody([[1, 1, 0, 1]]), { headerBytes: 64 }));
    expect(f.kind === 'particles' && f.particles.count).toBe(1);
  });

  it('refuse a body that disagrees with its count', () => {
    expect(() => decodeParticlesBody(particlesBody([[0, 0, 0, 1]], { count: 2 }), 0)).toThrow(FrameError);
    expect(() => decodeParticlesBody(particlesBody([[0, 0, 0, 1], [0, 0, 0, 1]], { count: 1 }), 0)).toThrow(FrameError);
    expect(() => decodeParticlesBody(new ArrayBuffer(8), 0)).toThrow(/too short/);
  });

  it('have a JSON twin', () => {
    const p = particlesFromJson({ count: 2, total: 300, particles: [[1, 2, 3, 0.5], [4, 5, 6, null]] });
    expect([p.count, p.total]).toEqual([2, 300]);
    expect([...p.data.slice(0, 4)]).toEqual([1, 2, 3, 0.5]);
    expect(Number.isNaN(p.data[7])).toBe(true);
    expect(() => particlesFromJson({ count: 3, total: 3, particles: [[0, 0, 0, 1]] })).toThrow(FrameError);
  });
});

describe('particle alpha by weight', () => {
  it('is 1 for the heaviest, the minimum for weight 0, linear between', () => {
    const set = particlesFromJson({ count: 3, total: 3, particles: [[0, 0, 0, 0.6], [0, 0, 0, 0.3], [0, 0, 0, 0]] });
    const alphas = particleAlphas(set);
    expect(alphas[0]).toBeCloseTo(1, 6);
    expect(alphas[1]).toBeCloseTo(MIN_PARTICLE_ALPHA + (1 - MIN_PARTICLE_ALPHA) * 0.5, 6);
    expect(alphas[2]).toBeCloseTo(MIN_PARTICLE_ALPHA, 6);
  });

  it('draws equal weights alike and bad weights faint', () => {
    const equal = particlesFromJson({ count: 2, total: 2, particles: [[0, 0, 0, 0.5], [1, 1, 0, 0.5]] });
    expect([...particleAlphas(equal)]).toEqual([1, 1]);
    const bad = particlesFromJson({ count: 2, total: 2, particles: [[0, 0, 0, -1], [1, 1, 0, null]] });
    expect([...particleAlphas(bad)].map((a) => a.toFixed(2))).toEqual([MIN_PARTICLE_ALPHA.toFixed(2), MIN_PARTICLE_ALPHA.toFixed(2)]);
  });

  it('gives the weighted mean position', () => {
    const set = particlesFromJson({ count: 2, total: 2, particles: [[0, 0, 0, 0.75], [4, 8, 0, 0.25]] });
    expect(weightedMean(set)).toEqual({ x: 1, y: 2 });
    expect(weightedMean(particlesFromJson({ count: 0, total: 0, particles: [] }))).toBeNull();
  });
});
