// The IR ring (the `ir` topic, e.g. the Dashgo D1's bumper-height IR sensors): readings shaped as
// the sonar's, drawn as lime wedges so the two rings tell apart. Counts the readings drawn.

import type { MapFrame, MapLayer, Redraw } from '../layer';
import { drawRangeCone } from './sonar';
import type { ConeStyle, SonarReading } from './sonar';

const IR_STYLE: ConeStyle = { fill: 'rgba(163, 230, 53, 0.16)', echo: 'rgba(163, 230, 53, 0.85)' };

export class IrLayer implements MapLayer {
  readonly id = 'ir';
  readonly toggle = 'ir';
  private readings: SonarReading[] = [];

  constructor(private readonly redraw: Redraw) {}

  set(readings: SonarReading[]): void {
    this.readings = readings;
    this.redraw();
  }

  get count(): number {
    return this.readings.length;
  }

  draw(frame: MapFrame): void {
    for (const reading of this.readings) drawRangeCone(frame, reading, IR_STYLE);
  }
}
