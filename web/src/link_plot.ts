// The Link card's plot: the last minute of round trips and frame ages on one ms axis, drawn on a
// canvas with no library. The geometry (samples -> polylines in the plot box, broken where a
// series has no value or samples are missing) is pure and unit-tested; drawLinkPlot paints it.

import { PLOT_WINDOW_MS, plotScaleMs, SAMPLE_PERIOD_MS, scaleValue, SERIES } from './link';
import type { LinkSample, SeriesKey } from './link';

/** The plot area inside the canvas, CSS pixels. */
export interface PlotBox {
  left: number;
  top: number;
  width: number;
  height: number;
}

/** Room for the axis labels: ms on the left, seconds below. */
const MARGIN = { left: 44, right: 8, top: 10, bottom: 18 };
/** Two samples further apart than this are not joined (the page was frozen, or hidden). */
const MAX_JOIN_MS = SAMPLE_PERIOD_MS * 3;

export function plotBox(widthPx: number, heightPx: number): PlotBox {
  return {
    left: MARGIN.left,
    top: MARGIN.top,
    width: Math.max(1, widthPx - MARGIN.left - MARGIN.right),
    height: Math.max(1, heightPx - MARGIN.top - MARGIN.bottom),
  };
}

/**
 * One series as polylines of [x, y] in the box: time runs from `nowMs - PLOT_WINDOW_MS` (left
 * edge) to `nowMs` (right edge), 0 ms at the bottom, `topMs` at the top; values above `topMs` are
 * drawn on the top edge. A line breaks at a missing value or a hole in the samples.
 */
export function seriesLines(samples: readonly LinkSample[], key: SeriesKey, nowMs: number, box: PlotBox, topMs: number): [number, number][][] {
  const lines: [number, number][][] = [];
  let line: [number, number][] = [];
  let previousAt = Number.NEGATIVE_INFINITY;
  for (const s of samples) {
    const value = s[key];
    if (value === null || s.atMs - previousAt > MAX_JOIN_MS) {
      if (line.length) lines.push(line);
      line = [];
    }
    previousAt = s.atMs;
    if (value === null) continue;
    const x = box.left + ((s.atMs - (nowMs - PLOT_WINDOW_MS)) / PLOT_WINDOW_MS) * box.width;
    const clipped = Math.min(Math.max(value, 0), topMs);
    line.push([x, box.top + box.height * (1 - clipped / topMs)]);
  }
  if (line.length) lines.push(line);
  return lines;
}

/** "0 ms", "25 ms", "1 s": a grid value as the axis says it. */
export function axisLabel(ms: number): string {
  return ms >= 1000 ? `${+(ms / 1000).toFixed(2)} s` : `${Math.round(ms)} ms`;
}

/** The ms values the horizontal grid lines mark: quarters of the axis. */
export function gridValues(topMs: number): number[] {
  return [0, 0.25, 0.5, 0.75, 1].map((f) => f * topMs);
}

const AXIS_COLOR = '#8b98a9';
const GRID_COLOR = 'rgba(139, 152, 169, 0.18)';

/** Paints the plot on `ctx` (already scaled to CSS pixels) of `widthPx` x `heightPx`; returns the axis top (ms). */
export function drawLinkPlot(ctx: CanvasRenderingContext2D, widthPx: number, heightPx: number, samples: readonly LinkSample[], nowMs: number): number {
  const box = plotBox(widthPx, heightPx);
  const topMs = plotScaleMs(scaleValue(samples));
  ctx.clearRect(0, 0, widthPx, heightPx);
  ctx.font = '10px ui-monospace, Menlo, Consolas, monospace';
  ctx.lineWidth = 1;
  // Grid and the ms axis.
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  for (const value of gridValues(topMs)) {
    const y = Math.round(box.top + box.height * (1 - value / topMs)) + 0.5;
    ctx.strokeStyle = GRID_COLOR;
    ctx.beginPath();
    ctx.moveTo(box.left, y);
    ctx.lineTo(box.left + box.width, y);
    ctx.stroke();
    if (value === 0 || value === topMs / 2 || value === topMs) {
      ctx.fillStyle = AXIS_COLOR;
      ctx.fillText(axisLabel(value), box.left - 4, y);
    }
  }
  // The time axis: seconds before now.
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
  for (const secondsAgo of [60, 45, 30, 15, 0]) {
    const x = box.left + box.width * (1 - (secondsAgo * 1000) / PLOT_WINDOW_MS);
    ctx.strokeStyle = GRID_COLOR;
    ctx.beginPath();
    ctx.moveTo(Math.round(x) + 0.5, box.top);
    ctx.lineTo(Math.round(x) + 0.5, box.top + box.height);
    ctx.stroke();
    ctx.fillStyle = AXIS_COLOR;
    ctx.textAlign = secondsAgo === 60 ? 'left' : secondsAgo === 0 ? 'right' : 'center';
    ctx.fillText(secondsAgo === 0 ? 'now' : `−${secondsAgo} s`, x, box.top + box.height + 4);
  }
  ctx.strokeStyle = AXIS_COLOR;
  ctx.strokeRect(box.left + 0.5, box.top + 0.5, box.width - 1, box.height - 1);
  // The series, clipped to the box.
  ctx.save();
  ctx.beginPath();
  ctx.rect(box.left, box.top, box.width, box.height);
  ctx.clip();
  ctx.lineWidth = 1.5;
  ctx.lineJoin = 'round';
  for (const series of SERIES) {
    ctx.strokeStyle = series.color;
    ctx.fillStyle = series.color;
    ctx.setLineDash(series.dashed ? [4, 3] : []);
    for (const line of seriesLines(samples, series.key, nowMs, box, topMs)) {
      if (line.length === 1) {
        // A lone value (one ping between outages): a dot, or it would not show at all.
        ctx.fillRect(line[0]![0] - 1.5, line[0]![1] - 1.5, 3, 3);
        continue;
      }
      ctx.beginPath();
      ctx.moveTo(line[0]![0], line[0]![1]);
      for (const [x, y] of line.slice(1)) ctx.lineTo(x, y);
      ctx.stroke();
    }
  }
  ctx.restore();
  return topMs;
}
