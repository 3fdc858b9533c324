// The Link card of the Live page: a live plot of the last minute (round trip by ping and by teleop
// echo, age of the pose and of the scan on screen), the newest values in its legend, the clock
// offset the ages use, bytes received per second, frames dropped, and the per-topic table. It
// samples the link at 4 Hz whatever page is shown (the history is whole when one comes back) and
// draws only while the card can be seen. The numbers are link.ts's; the drawing link_plot.ts's.

import { localWallMs } from './clock_offset';
import { LinkMonitor, msText, rateText, SAMPLE_PERIOD_MS, SERIES } from './link';
import type { LinkSample, SeriesKey } from './link';
import { drawLinkPlot } from './link_plot';
import type { Pong, StreamClient, TeleopAck } from './stream';
import { byId, fmt, h } from './ui';

/** The per-topic table and the drop counts change slowly: once a second is enough. */
const TABLE_PERIOD_MS = 1000;

/** min / max / count of one series over a stretch of the history (test hooks, the report). */
export interface SeriesSummary {
  min: number | null;
  max: number | null;
  count: number;
}

export class LinkPanel {
  readonly monitor = new LinkMonitor();
  /** Plots drawn (the canvas's data-drawn), for the browser test. */
  drawn = 0;
  private readonly canvas: HTMLCanvasElement;
  private readonly values = new Map<SeriesKey, HTMLElement>();
  private visible = true;
  private lastTableAt = 0;

  constructor(private readonly stream: StreamClient) {
    this.canvas = byId<HTMLCanvasElement>('link-plot');
    this.buildLegend();
    window.setInterval(() => this.tick(), SAMPLE_PERIOD_MS);
  }

  // ---- what the stream tells ----

  onPong(pong: Pong): void {
    this.monitor.onPong(pong.sentMs, pong.receivedMs, pong.wallUs);
  }

  onTeleopAck(ack: TeleopAck): void {
    if (ack.rttMs !== null) this.monitor.onTeleopEcho(ack.rttMs, localWallMs());
  }

  /** A pose frame handed to the map (drawn at the next animation frame). */
  onPose(wallUs: number | undefined): void {
    this.monitor.onPose(wallUs);
  }

  onScan(wallUs: number | undefined): void {
    this.monitor.onScan(wallUs);
  }

  disconnected(): void {
    this.monitor.disconnected();
  }

  /** The Live page is shown (the plot is drawn only then). */
  setVisible(visible: boolean): void {
    this.visible = visible;
  }

  // ---- numbers for the hooks ----

  /** Dropped frames on full-rate topics, and seq gaps on thinned ones. */
  gaps(): { dropped: number; thinned: number } {
    return this.stream.stats.gapsByKind(this.stream.thinnedTopics);
  }

  /** Each series over the last `seconds` of the history. */
  summary(seconds: number): Record<SeriesKey, SeriesSummary> {
    const since = localWallMs() - seconds * 1000;
    const out = {} as Record<SeriesKey, SeriesSummary>;
    for (const { key } of SERIES) {
      const values = this.monitor
        .history()
        .filter((s) => s.atMs >= since)
        .map((s) => s[key])
        .filter((v): v is number => v !== null);
      out[key] = { min: values.length ? Math.min(...values) : null, max: values.length ? Math.max(...values) : null, count: values.length };
    }
    return out;
  }

  // ---- rendering ----

  private tick(): void {
    const now = localWallMs();
    const sample = this.monitor.sample(now, this.stream.bytesReceived, this.stream.connected);
    this.canvas.dataset.samples = String(this.monitor.history().length);
    if (!this.visible || document.hidden) return;
    this.showValues(sample, now);
    this.draw(now);
    if (now - this.lastTableAt >= TABLE_PERIOD_MS) {
      this.lastTableAt = now;
      this.showTable(now);
    }
  }

  private buildLegend(): void {
    const legend = byId('link-legend');
    const testIds: Record<SeriesKey, string> = { pingRttMs: 'latency-rtt', teleopRttMs: 'latency-teleop', poseAgeMs: 'age-pose', scanAgeMs: 'age-scan' };
    legend.replaceChildren(
      ...SERIES.map((series) => {
        const value = h('span', { class: 'mono value', testid: testIds[series.key], text: '–' });
        this.values.set(series.key, value);
        const swatch = h('span', { class: `swatch${series.dashed ? ' dashed' : ''}` });
        swatch.style.setProperty('--series', series.color);
        return h('li', { title: series.title, attrs: { 'data-series': series.key } }, swatch, h('span', { class: 'label', text: series.label }), value);
      }),
    );
  }

  private showValues(sample: LinkSample, now: number): void {
    // As plotted: the newest sample (the top bar has the smoothed ping round trip).
    for (const { key } of SERIES) this.values.get(key)!.textContent = msText(sample[key]);
    byId('conn-rtt').textContent = this.stream.connected && this.stream.rttMs !== null ? msText(this.stream.rttMs) : '';
    const offset = this.monitor.currentOffset(now);
    const offsetEl = byId('lnk-offset');
    if (offset) {
      offsetEl.textContent = `${offset.offsetMs >= 0 ? '+' : ''}${msText(offset.offsetMs)} ± ${msText(offset.rttMs / 2)}`;
      offsetEl.title = 'server wall clock minus this computer\'s, from the fastest pong of the last 30 s (good to half its round trip); the ages use it';
    } else {
      offsetEl.textContent = this.monitor.offsetMeasured ? 'no recent pong' : 'not measured: clocks taken as in sync';
      offsetEl.title = 'the server\'s pongs carry no wall_us: the ages assume this computer\'s clock agrees with the server\'s (same machine, or NTP)';
    }
    byId('lnk-rate').textContent = rateText(this.monitor.bytesPerSecond());
    const gaps = this.gaps();
    byId('lnk-gaps').textContent = String(gaps.dropped);
    const thinned = byId('lnk-thinned');
    thinned.hidden = gaps.thinned === 0;
    thinned.textContent = `· ${gaps.thinned} gaps on thinned topics (${[...this.stream.thinnedTopics].join(', ') || 'none now'})`;
  }

  private draw(now: number): void {
    const width = this.canvas.clientWidth;
    const height = this.canvas.clientHeight;
    if (width === 0 || height === 0) return;
    const ratio = window.devicePixelRatio || 1;
    if (this.canvas.width !== Math.round(width * ratio) || this.canvas.height !== Math.round(height * ratio)) {
      this.canvas.width = Math.round(width * ratio);
      this.canvas.height = Math.round(height * ratio);
    }
    const ctx = this.canvas.getContext('2d');
    if (!ctx) return;
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    const topMs = drawLinkPlot(ctx, width, height, this.monitor.history(), now);
    this.drawn++;
    this.canvas.dataset.drawn = String(this.drawn);
    this.canvas.dataset.topMs = String(topMs);
  }

  private showTable(now: number): void {
    const stats = this.stream.stats;
    // publish -> receipt as measured against this computer's clock, corrected by the offset.
    const offsetMs = this.monitor.currentOffset(now)?.offsetMs ?? 0;
    const body = byId('topics').querySelector('tbody')!;
    body.replaceChildren(
      ...stats.entries().map(([topic, s]) => {
        const thinned = this.stream.thinnedTopics.has(topic);
        return h(
          'tr',
          { testid: `topic-${topic}` },
          h('td', { text: topic }),
          h('td', { class: 'mono', text: fmt(s.rateHz, 1) }),
          h('td', {
            class: `mono${s.gaps && !thinned ? ' warn' : ''}`,
            text: thinned ? `${s.gaps} (thinned)` : String(s.gaps),
            title: thinned ? 'subscribed with max_rate_hz: most gaps are the thinning asked for' : 'frames the server dropped for this page, or lost',
          }),
          h('td', { class: 'mono', text: s.latencyMs === null ? '–' : msText(s.latencyMs + offsetMs) }),
        );
      }),
    );
  }
}
