// The position uncertainty of the estimated pose: the UNCERTAINTY_SIGMAS ellipse of the x-y block
// of the pose covariance, drawn over the robot.

import { covarianceEllipse } from '../../goals';
import type { MapFrame, MapLayer } from '../layer';

/** Sigmas of the drawn uncertainty (this ellipse and the heading wedge). */
export const UNCERTAINTY_SIGMAS = 2;

const FILL = 'rgba(56, 189, 248, 0.16)';
const STROKE = 'rgba(125, 211, 252, 0.95)';
/** Sub-pixel uncertainty still shows as a small ring at the estimate. */
const MIN_RADIUS_PX = 3;

export class CovarianceEllipseLayer implements MapLayer {
  readonly id = 'covariance';
  readonly toggle = 'cov';
  readonly showsRobot = true;

  draw({ ctx, view, scene }: MapFrame): void {
    const { pose, cov } = scene;
    if (!pose || !cov) return;
    const ellipse = covarianceEllipse(cov, UNCERTAINTY_SIGMAS);
    if (!ellipse) return;
    const [cx, cy] = view.toScreen(pose.x, pose.y);
    const rx = Math.max(MIN_RADIUS_PX, ellipse.major * view.scale);
    const ry = Math.max(MIN_RADIUS_PX, ellipse.minor * view.scale);
    ctx.beginPath();
    // Screen angles are the map angles negated (y down).
    ctx.ellipse(cx, cy, rx, ry, -ellipse.angle, 0, 2 * Math.PI);
    ctx.fillStyle = FILL;
    ctx.fill();
    ctx.strokeStyle = STROKE;
    ctx.lineWidth = 1.5;
    ctx.stroke();
  }
}
