// The simulator's true pose (the `truth` topic) as a dashed ghost of the footprint, under the
// estimate, so localisation error shows as the two footprints parting.

import type { Pose2D } from '../../frames';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawFootprint } from './robot';

export class TruthLayer implements MapLayer {
  readonly id = 'truth';
  readonly toggle = 'truth';
  readonly showsRobot = true;
  private pose: Pose2D | null = null;

  constructor(private readonly redraw: Redraw) {}

  /** The true pose, or null when the backend has none (not a simulator). */
  set(pose: Pose2D | null): void {
    this.pose = pose;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    if (this.pose) drawFootprint(ctx, view, this.pose, true);
  }
}
