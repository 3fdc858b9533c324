// The simulator's true pose (the `truth` topic) as a dashed ghost of the robot's outline (the
// square footprint, or a tricycle's body), under the estimate, so localisation error shows as the
// two outlines parting.

import type { Pose2D } from '../../frames';
import { DIFFERENTIAL, sameBody } from '../../tricycle';
import type { RobotBody } from '../../tricycle';
import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawFootprint, drawTricycle } from './robot';

export class TruthLayer implements MapLayer {
  readonly id = 'truth';
  readonly toggle = 'truth';
  readonly showsRobot = true;
  private pose: Pose2D | null = null;
  private body: RobotBody = DIFFERENTIAL;

  constructor(private readonly redraw: Redraw) {}

  /** The true pose, or null when the backend has none (not a simulator). */
  set(pose: Pose2D | null): void {
    this.pose = pose;
    this.redraw();
  }

  /** The robot's body (as the robot layer draws it). */
  setBody(body: RobotBody): void {
    if (sameBody(body, this.body)) return;
    this.body = body;
    this.redraw();
  }

  draw({ ctx, view }: MapFrame): void {
    if (!this.pose) return;
    if (this.body.kind === 'tricycle') drawTricycle(ctx, view, this.pose, this.body.geometry, 0, true);
    else drawFootprint(ctx, view, this.pose, true);
  }
}
