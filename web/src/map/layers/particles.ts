// The particle filter's belief (the `particles` topic): each particle as a short arrow along its
// heading, or a dot when zoomed out, its alpha by weight (particles.ts). Alphas are bucketed so a
// frame strokes a handful of paths, not one per particle. The particles drawn are published as the
// canvas's data-particles.

import { PARTICLE_FLOATS, particleAlphas } from '../../particles';
import type { ParticleSet } from '../../particles';
import type { MapFrame, MapLayer, Redraw } from '../layer';

export const PARTICLE_COLOR = '#e879f9';
/** Alpha levels a frame draws with. */
const BUCKETS = 8;
/** Below this many pixels per metre the particles are dots. */
const ARROW_MIN_SCALE = 30;
const DOT_PX = 2.5;

export class ParticlesLayer implements MapLayer {
  readonly id = 'particles';
  readonly toggle = 'particles';
  readonly showsRobot = true;
  /** Particles in the last frame drawn. */
  drawn = 0;
  /** Frames of the topic drawn (a set redrawn for a pan counts once). */
  setsDrawn = 0;
  private set_: ParticleSet | null = null;
  private buckets: Uint8Array = new Uint8Array(0);
  private fresh = false;

  constructor(private readonly redraw: Redraw) {}

  /** The sample to draw, or null (the filter stopped). */
  set(particles: ParticleSet | null): void {
    this.set_ = particles;
    if (particles) {
      const alphas = particleAlphas(particles);
      this.buckets = Uint8Array.from(alphas, (a) => Math.min(BUCKETS - 1, Math.floor(a * BUCKETS)));
    }
    this.fresh = true;
    this.redraw();
  }

  get current(): ParticleSet | null {
    return this.set_;
  }

  draw({ ctx, view, canvas }: MapFrame): void {
    const set = this.set_;
    let drawn = 0;
    if (set && set.count > 0) {
      const arrows = view.scale >= ARROW_MIN_SCALE;
      const length = Math.max(7, Math.min(14, 0.2 * view.scale));
      ctx.strokeStyle = PARTICLE_COLOR;
      ctx.fillStyle = PARTICLE_COLOR;
      ctx.lineWidth = 1.25;
      for (let b = 0; b < BUCKETS; b++) {
        ctx.globalAlpha = (b + 1) / BUCKETS;
        ctx.beginPath();
        for (let i = 0; i < set.count; i++) {
          if (this.buckets[i] !== b) continue;
          const x = set.data[i * PARTICLE_FLOATS]!;
          const y = set.data[i * PARTICLE_FLOATS + 1]!;
          const theta = set.data[i * PARTICLE_FLOATS + 2]!;
          if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
          const sx = view.toScreenX(x);
          const sy = view.toScreenY(y);
          if (arrows && Number.isFinite(theta)) {
            const ux = Math.cos(theta);
            const uy = -Math.sin(theta);
            const ex = sx + ux * length;
            const ey = sy + uy * length;
            ctx.moveTo(sx, sy);
            ctx.lineTo(ex, ey);
            // A small open head.
            ctx.moveTo(ex - ux * 3.5 - uy * 2.5, ey - uy * 3.5 + ux * 2.5);
            ctx.lineTo(ex, ey);
            ctx.lineTo(ex - ux * 3.5 + uy * 2.5, ey - uy * 3.5 - ux * 2.5);
          } else {
            ctx.rect(sx - DOT_PX / 2, sy - DOT_PX / 2, DOT_PX, DOT_PX);
          }
          drawn++;
        }
        if (arrows) ctx.stroke();
        else ctx.fill();
      }
      ctx.globalAlpha = 1;
      if (this.fresh) {
        this.fresh = false;
        this.setsDrawn++;
      }
    }
    this.drawn = drawn;
    const text = String(drawn);
    if (canvas.dataset.particles !== text) canvas.dataset.particles = text;
  }
}
