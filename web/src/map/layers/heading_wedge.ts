// The heading uncertainty of the estimated pose: a wedge of +-UNCERTAINTY_SIGMAS sigma(theta)
// around the estimated heading, drawn under the robot.

import { headingSigma } from '../../goals';
import type { MapFrame, MapLayer } from '../layer';
import { UNCERTAINTY_SIGMAS } from './covariance_ellipse';
import { FOOTPRINT_M } from './robot';

const FILL = 'rgba(250, 204, 21, 0.22)';
const STROKE = 'rgba(250, 204, 21, 0.8)';
/** The wedge reaches past the footprint, and at least this far on screen. */
const MIN_RADIUS_PX = 26;
/** Narrowest half-angle drawn (rad): a certain heading still shows as a line. */
const MIN_HALF_ANGLE = 0.004;

export class HeadingWedgeLayer implements MapLayer {
  readonly id = 'headingWedge';
  readonly toggle = 'cov';
  readonly showsRobot = true;

  draw({ ctx, view, scene }: MapFrame): void {
    const { pose, cov } = scene;
    if (!pose || !cov) return;
    const sigmaTheta = headingSigma(cov);
    if (sigmaTheta === null) return;
    const half = Math.max(Math.min(Math.PI, UNCERTAINTY_SIGMAS * sigmaTheta), MIN_HALF_ANGLE);
    const radius = Math.max(MIN_RADIUS_PX, FOOTPRINT_M * 1.25 * view.scale);
    const [cx, cy] = view.toScreen(pose.x, pose.y);
    ctx.beginPath();
    ctx.moveTo(cx, cy);
    // Screen angles are the map angles negated (y down).
    ctx.arc(cx, cy, radius, -pose.theta - half, -pose.theta + half);
    ctx.closePath();
    ctx.fillStyle = FILL;
    ctx.fill();
    ctx.strokeStyle = STROKE;
    ctx.lineWidth = 1;
    ctx.stroke();
  }
}
