// The particle filter's belief (the `particles` topic, binary topic id 6, README "Binary frames"):
// a weighted sample of at most 2000 particles, x, y, theta in the map frame and a weight (the
// sample's weights sum to 1). Decoders of both encodings and the drawn alpha of each particle.
// Pure (no DOM), unit-tested.

import { FrameError } from './frame_error';

export const PARTICLES_BODY_HEADER_BYTES = 32;
export const PARTICLE_FLOATS = 4;

export interface ParticleSet {
  /** Particles in this sample. */
  count: number;
  /** Particles in the filter (the sample is drawn from them). */
  total: number;
  /** PARTICLE_FLOATS per particle: x, y, theta (map frame), weight. */
  data: Float32Array;
}

/** The particles body at `bodyOffset`: it must hold exactly `count` particles. */
export function decodeParticlesBody(buffer: ArrayBuffer, bodyOffset: number): ParticleSet {
  if (buffer.byteLength < bodyOffset + PARTICLES_BODY_HEADER_BYTES) throw new FrameError('particles body too short');
  const view = new DataView(buffer, bodyOffset);
  const count = view.getUint32(0, true);
  const total = view.getUint32(4, true);
  const bytes = buffer.byteLength - bodyOffset - PARTICLES_BODY_HEADER_BYTES;
  const expected = count * PARTICLE_FLOATS * 4;
  if (bytes !== expected) throw new FrameError(`particles body holds ${bytes} bytes, count ${count} says ${expected}`);
  const offset = bodyOffset + PARTICLES_BODY_HEADER_BYTES;
  const floats = count * PARTICLE_FLOATS;
  // Aligned offsets (the header is 32 bytes) view the buffer without copying.
  const data = offset % 4 === 0 ? new Float32Array(buffer, offset, floats) : new Float32Array(buffer.slice(offset, offset + floats * 4));
  return { count, total, data };
}

export interface JsonParticles {
  count: number;
  total: number;
  particles: unknown;
}

/** `{"count","total","particles":[[x,y,theta,w],...]}`; a null (NaN) value drops nothing, it is kept as NaN. */
export function particlesFromJson(json: JsonParticles): ParticleSet {
  const rows = Array.isArray(json.particles) ? (json.particles as unknown[]) : [];
  if (rows.length !== json.count) throw new FrameError(`particles JSON holds ${rows.length} particles, count says ${json.count}`);
  const data = new Float32Array(rows.length * PARTICLE_FLOATS);
  rows.forEach((row, i) => {
    for (let k = 0; k < PARTICLE_FLOATS; k++) {
      const v = Array.isArray(row) ? row[k] : undefined;
      data[i * PARTICLE_FLOATS + k] = typeof v === 'number' ? v : NaN;
    }
  });
  return { count: rows.length, total: typeof json.total === 'number' ? json.total : rows.length, data };
}

/** Drawn alpha of the lightest particle: it still shows. */
export const MIN_PARTICLE_ALPHA = 0.15;

/**
 * Alpha per particle, by weight relative to the heaviest of the sample: MIN_PARTICLE_ALPHA for
 * weight 0, 1 for the heaviest. Equal weights (a fresh filter) are all opaque; a non-finite or
 * negative weight counts as 0.
 */
export function particleAlphas(set: ParticleSet, minAlpha = MIN_PARTICLE_ALPHA): Float32Array {
  const alphas = new Float32Array(set.count);
  let max = 0;
  for (let i = 0; i < set.count; i++) {
    const w = set.data[i * PARTICLE_FLOATS + 3]!;
    if (Number.isFinite(w) && w > max) max = w;
  }
  for (let i = 0; i < set.count; i++) {
    const w = set.data[i * PARTICLE_FLOATS + 3]!;
    const k = max > 0 && Number.isFinite(w) && w > 0 ? w / max : 0;
    alphas[i] = minAlpha + (1 - minAlpha) * k;
  }
  return alphas;
}

/** Weighted mean position of the sample (null when no weight is positive). */
export function weightedMean(set: ParticleSet): { x: number; y: number } | null {
  let sw = 0;
  let sx = 0;
  let sy = 0;
  for (let i = 0; i < set.count; i++) {
    const x = set.data[i * PARTICLE_FLOATS]!;
    const y = set.data[i * PARTICLE_FLOATS + 1]!;
    const w = set.data[i * PARTICLE_FLOATS + 3]!;
    if (!(w > 0) || !Number.isFinite(x) || !Number.isFinite(y)) continue;
    sw += w;
    sx += w * x;
    sy += w * y;
  }
  return sw > 0 ? { x: sx / sw, y: sy / sw } : null;
}
